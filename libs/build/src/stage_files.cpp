#include "stage_files.h"

#include <zstd.h>

#include <fstream>

#include "terralod/core/atomic_file.h"
#include "terralod/format/tileset_format.h"

namespace terralod {
namespace {

constexpr char kStageMagic[8] = {'T', 'L', 'S', 'T', 'A', 'G', 'E', '1'};
constexpr size_t kStageHeaderBytes = 8 + 4 + 8 + 8 + 4;

}  // namespace

Status writeStageFile(const std::string& path, StageFile kind, std::span<const uint8_t> payload) {
  std::vector<uint8_t> compressed;
  std::span<const uint8_t> packed = payload;
  if (!storedRaw(kind)) {
    compressed.resize(ZSTD_compressBound(payload.size()));
    const size_t n =
        ZSTD_compress(compressed.data(), compressed.size(), payload.data(), payload.size(), 1);
    if (ZSTD_isError(n)) return makeError(path, std::string("zstd: ") + ZSTD_getErrorName(n));
    compressed.resize(n);
    packed = compressed;
  }
  std::vector<uint8_t> header(kStageHeaderBytes);
  ByteWriter w(header.data());
  w.putBytes(kStageMagic, sizeof kStageMagic);
  w.put(uint32_t(kind));
  w.put(uint64_t(payload.size()));
  w.put(uint64_t(packed.size()));
  w.put(crc32Of(packed));
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  if (Status s = file->write(header); !s) return s;
  if (Status s = file->write(packed); !s) return s;
  // Atomic, not synced: a file lost with its node is made again by the task that wrote it, and
  // one damaged is refused (CRC) rather than read.
  return file->commit(AtomicFile::Durability::kUnsynced);
}

Result<StagePayload> readStageFile(const std::string& path, StageFile kind) {
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) return makeError(path, "missing (the stage that writes it has not run, or failed)");
  const size_t fileBytes = size_t(in.tellg());
  in.seekg(0);
  uint8_t header[kStageHeaderBytes];
  if (fileBytes < kStageHeaderBytes || !in.read(reinterpret_cast<char*>(header), sizeof header) ||
      std::memcmp(header, kStageMagic, sizeof kStageMagic) != 0)
    return makeError(path, "not a terralod stage file");
  ByteReader r(header + sizeof kStageMagic);
  const uint32_t fileKind = r.get<uint32_t>();
  const uint64_t rawBytes = r.get<uint64_t>(), packedBytes = r.get<uint64_t>();
  const uint32_t crc = r.get<uint32_t>();
  if (fileKind != uint32_t(kind))
    return makeError(path, "is a stage file of another kind (" + std::to_string(fileKind) +
                               ", expected " + std::to_string(uint32_t(kind)) + ")");
  if (fileBytes - kStageHeaderBytes != packedBytes || (storedRaw(kind) && rawBytes != packedBytes))
    return makeError(path, "damaged (size or checksum does not match)");
  auto packed = std::make_unique_for_overwrite<uint8_t[]>(packedBytes);
  if (!in.read(reinterpret_cast<char*>(packed.get()), std::streamsize(packedBytes)))
    return makeError(path, "cannot be read");
  if (crc32Of({packed.get(), packedBytes}) != crc)
    return makeError(path, "damaged (size or checksum does not match)");
  if (storedRaw(kind)) return StagePayload(std::move(packed), packedBytes);
  auto payload = std::make_unique_for_overwrite<uint8_t[]>(rawBytes);
  const size_t n = ZSTD_decompress(payload.get(), rawBytes, packed.get(), packedBytes);
  if (ZSTD_isError(n) || n != rawBytes) return makeError(path, "damaged (does not decompress)");
  return StagePayload(std::move(payload), rawBytes);
}

}  // namespace terralod
