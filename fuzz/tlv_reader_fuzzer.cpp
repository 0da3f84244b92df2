// Fuzzes the vegetation file reader and the LDI codec on untrusted bytes. Input: one mode
// byte, then the data; mode & 3 selects:
//   0  a .tlv file, its checksums first recomputed as a writer would (header, settings,
//      directory, every blob the directory points at), so mutations get past them;
//   1  a .tlv file read exactly as given (the mismatch paths);
//   2  one LDI blob, decoded as given;
//   3  an LDI blob's 80-byte header, then its payload uncompressed: the harness compresses
//      it, so mutations reach the plane decoding behind zstd.
// Files are opened with VegetationReader::open over a memory source, then every LDI is read.

#include <zstd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <vector>

#include "terralod/format/byte_source.h"
#include "terralod/format/tileset_format.h"  // crc32Of
#include "terralod/vegetation/vegetation_file.h"

namespace {

using namespace terralod::veg;

template <typename T>
T load(const std::vector<uint8_t>& b, uint64_t at) {
  T v{};
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}
bool inside(const std::vector<uint8_t>& b, uint64_t offset, uint64_t length) {
  return offset <= b.size() && length <= b.size() - offset;
}
void storeCrc(std::vector<uint8_t>& b, uint64_t at, uint64_t from, uint64_t length) {
  if (!inside(b, at, 4) || !inside(b, from, length)) return;
  const uint32_t crc = terralod::crc32Of(std::span(b).subspan(from, length));
  std::memcpy(b.data() + at, &crc, sizeof crc);
}

// Offsets in the file header and in a directory record (docs/format.md).
constexpr uint64_t kSettingsOffset = 32, kSettingsBytes = 40, kDirectoryOffset = 48,
                   kDirectoryBytes = 56, kSettingsCrc = 88, kDirectoryCrc = 92, kHeaderCrc = 124;
constexpr uint64_t kEntryOffset = 0, kEntryBytes = 8, kEntryCrc = 36;

void fixChecksums(std::vector<uint8_t>& b) {
  if (b.size() < tlv::kHeaderBytes) return;
  const uint64_t directory = load<uint64_t>(b, kDirectoryOffset);
  const uint64_t directoryBytes = load<uint64_t>(b, kDirectoryBytes);
  if (inside(b, directory, directoryBytes)) {
    for (uint64_t e = directory; e + tlv::kDirectoryRecordBytes <= directory + directoryBytes;
         e += tlv::kDirectoryRecordBytes)
      storeCrc(b, e + kEntryCrc, load<uint64_t>(b, e + kEntryOffset),
               load<uint64_t>(b, e + kEntryBytes));
    storeCrc(b, kDirectoryCrc, directory, directoryBytes);
  }
  storeCrc(b, kSettingsCrc, load<uint64_t>(b, kSettingsOffset), load<uint64_t>(b, kSettingsBytes));
  storeCrc(b, kHeaderCrc, 0, kHeaderCrc);
}

// What a decoded LDI promises a renderer (docs/format.md, "What a reader validates").
void checkLdi(const Ldi& ldi) {
  const LdiCamera& c = ldi.camera;
  if (c.width < 1 || c.width > 4096 || c.height < 1 || c.height > 4096) __builtin_trap();
  if (ldi.layerCounts.size() != uint64_t(c.width) * c.height) __builtin_trap();
  uint64_t sum = 0;
  for (uint8_t n : ldi.layerCounts) sum += n;
  if (sum != ldi.pixels.size()) __builtin_trap();
  for (const DepthPixel& p : ldi.pixels)
    if ((p.zsplat >> 31) != 0 || p.splat() > kLdiMaxSplatCode) __builtin_trap();
  if (!std::isfinite(c.pixelSize) || !(c.pixelSize > 0)) __builtin_trap();
  if (!std::isfinite(c.depthMax - c.depthMin) || !(c.depthMax > c.depthMin)) __builtin_trap();
}

// What an opened reader promises: every blob inside the file, after the tables.
void checkReader(const VegetationReader& r) {
  using Wide = unsigned __int128;
  for (int t = 0; t < kPrototiles; ++t)
    for (int res = 0; res < kLdiResolutions; ++res)
      for (int d = 0; d < kLdiDirections; ++d) {
        const LdiEntry& e = r.entry(t, res, d);
        if (e.offset < tlv::kHeaderBytes || Wide(e.offset) + e.bytes > r.fileBytes())
          __builtin_trap();
        auto ldi = r.readLdi(t, res, d);
        if (!ldi) continue;
        checkLdi(*ldi);
        if (ldi->camera.width != e.width || ldi->pixels.size() != e.depthPixels) __builtin_trap();
      }
  if (r.readLdi(kPrototiles, 0, 0).ok()) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const int mode = data[0] & 3;
  std::vector<uint8_t> bytes(data + 1, data + size);
  if (mode <= 1) {
    if (mode == 0) fixChecksums(bytes);
    auto reader = VegetationReader::open(terralod::makeMemorySource(bytes, "fuzz.tlv"));
    if (reader) checkReader(**reader);
    return 0;
  }
  if (mode == 3) {
    if (bytes.size() < 80) return 0;
    static ZSTD_CCtx* const context = ZSTD_createCCtx();
    std::vector<uint8_t> blob(bytes.begin(), bytes.begin() + 80);
    blob.resize(80 + ZSTD_compressBound(bytes.size() - 80));
    const size_t n = ZSTD_compressCCtx(context, blob.data() + 80, blob.size() - 80,
                                       bytes.data() + 80, bytes.size() - 80, 1);
    if (ZSTD_isError(n)) __builtin_trap();
    blob.resize(80 + n);
    bytes = std::move(blob);
  }
  auto ldi = decodeLdi(bytes.data(), bytes.size());
  if (!ldi) return 0;
  checkLdi(*ldi);
  // A decoded LDI encodes back to a blob that decodes to the same LDI (small ones: this
  // compresses at the file's level, slow on the 16 MiB a tiny frame may hold).
  if (ldi->layerCounts.size() + 9 * ldi->pixels.size() > (size_t{1} << 20)) return 0;
  const std::vector<uint8_t> again = encodeLdi(*ldi);
  auto back = decodeLdi(again.data(), again.size());
  if (!back || !(*back == *ldi)) __builtin_trap();
  return 0;
}
