#include "stage_files.h"

#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "terralod/core/atomic_file.h"
#include "terralod/format/tileset_format.h"

namespace terralod {
namespace {

constexpr char kStageMagic[8] = {'T', 'L', 'S', 'T', 'A', 'G', 'E', '1'};
constexpr size_t kStageHeaderBytes = 8 + 4 + 8 + 8 + 4;

std::vector<uint8_t> stageHeader(StageFile kind, uint64_t rawBytes, uint64_t packedBytes,
                                 uint32_t crc) {
  std::vector<uint8_t> header(kStageHeaderBytes);
  ByteWriter w(header.data());
  w.putBytes(kStageMagic, sizeof kStageMagic);
  w.put(uint32_t(kind));
  w.put(rawBytes);
  w.put(packedBytes);
  w.put(crc);
  return header;
}

// What a stage file's header says, once its magic, kind and sizes are checked; `in` is left
// at the payload.
struct StageHeader {
  uint64_t rawBytes = 0, packedBytes = 0;
  uint32_t crc = 0;
};
Result<StageHeader> openStageFile(const std::string& path, StageFile kind, std::ifstream& in) {
  if (!in) return makeError(path, "missing (the stage that writes it has not run, or failed)");
  in.seekg(0, std::ios::end);
  const size_t fileBytes = size_t(in.tellg());
  in.seekg(0);
  uint8_t header[kStageHeaderBytes];
  if (fileBytes < kStageHeaderBytes || !in.read(reinterpret_cast<char*>(header), sizeof header) ||
      std::memcmp(header, kStageMagic, sizeof kStageMagic) != 0)
    return makeError(path, "not a terralod stage file");
  ByteReader r(header + sizeof kStageMagic);
  const uint32_t fileKind = r.get<uint32_t>();
  StageHeader h;
  h.rawBytes = r.get<uint64_t>();
  h.packedBytes = r.get<uint64_t>();
  h.crc = r.get<uint32_t>();
  if (fileKind != uint32_t(kind))
    return makeError(path, "is a stage file of another kind (" + std::to_string(fileKind) +
                               ", expected " + std::to_string(uint32_t(kind)) + ")");
  if (fileBytes - kStageHeaderBytes != h.packedBytes ||
      (storedRaw(kind) && h.rawBytes != h.packedBytes))
    return makeError(path, "damaged (size or checksum does not match)");
  return h;
}

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
  const std::vector<uint8_t> header =
      stageHeader(kind, payload.size(), packed.size(), crc32Of(packed));
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  if (Status s = file->write(header); !s) return s;
  if (Status s = file->write(packed); !s) return s;
  // Atomic, not synced: a file lost with its node is made again by the task that wrote it, and
  // one damaged is refused (CRC) rather than read.
  return file->commit(AtomicFile::Durability::kUnsynced);
}

Result<StagePayload> readStageFile(const std::string& path, StageFile kind) {
  std::ifstream in(path, std::ios::binary);
  auto h = openStageFile(path, kind, in);
  if (!h) return h.error();
  const uint64_t rawBytes = h->rawBytes, packedBytes = h->packedBytes;
  const uint32_t crc = h->crc;
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

Status writeBlockRecords(const std::string& path, StageFile kind,
                         const std::vector<std::vector<uint8_t>>& records) {
  Packer p;
  size_t bytes = 8;
  for (const auto& r : records) bytes += 8 + r.size();
  p.reserve(bytes);
  p.put(uint64_t(records.size()));
  for (const auto& r : records) p.putBytes(r);
  return writeStageFile(path, kind, p.bytes());
}

std::vector<uint8_t> compressedRecord(std::span<const uint8_t> raw) {
  std::vector<uint8_t> frame(ZSTD_compressBound(raw.size()));
  const size_t n = ZSTD_compress(frame.data(), frame.size(), raw.data(), raw.size(), 1);
  frame.resize(ZSTD_isError(n) ? 0 : n);  // cannot fail with a bound-sized buffer
  // A job holds a record per block until it writes them: at the bound's capacity, a pass-1
  // job's records held 16 MB for the 1 MB they use.
  frame.shrink_to_fit();
  return frame;
}

Status decompressRecord(std::span<const uint8_t> record, std::span<uint8_t> out,
                        const std::string& path) {
  const unsigned long long size = ZSTD_getFrameContentSize(record.data(), record.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    return makeError(path, "damaged (does not decompress)");
  if (size != out.size()) return makeError(path, "was written for another block layout");
  const size_t n = ZSTD_decompress(out.data(), out.size(), record.data(), record.size());
  if (ZSTD_isError(n) || n != out.size()) return makeError(path, "damaged (does not decompress)");
  return {};
}

Result<std::vector<uint8_t>> decompressRecord(std::span<const uint8_t> record, size_t maxBytes,
                                              const std::string& path) {
  const unsigned long long size = ZSTD_getFrameContentSize(record.data(), record.size());
  if (size == ZSTD_CONTENTSIZE_ERROR || size == ZSTD_CONTENTSIZE_UNKNOWN)
    return makeError(path, "damaged (does not decompress)");
  if (size > maxBytes) return makeError(path, "was written for another block layout");
  std::vector<uint8_t> out(static_cast<size_t>(size));
  if (Status st = decompressRecord(record, out, path); !st) return st.error();
  return out;
}

Result<BlockRecords> BlockRecords::read(const std::string& path, StageFile kind, size_t blocks) {
  auto payload = readStageFile(path, kind);
  if (!payload) return payload.error();
  BlockRecords out(std::move(*payload));
  Unpacker u(out.mPayload.bytes());
  const uint64_t count = u.get<uint64_t>();
  if (u.ok() && count != blocks) return makeError(path, "was written for another block layout");
  for (uint64_t i = 0; u.ok() && i < count; ++i) out.mRecords.push_back(u.getView());
  if (!u.ok() || !u.atEnd()) return makeError(path, "damaged (records do not add up)");
  return out;
}

Result<StageFileWriter> StageFileWriter::create(const std::string& path, StageFile kind) {
  if (!storedRaw(kind)) return Error{"internal error: only stored-raw stage files are streamed"};
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  if (Status s = file->write(stageHeader(kind, 0, 0, 0)); !s) return s.error();
  return StageFileWriter(std::move(*file), kind);
}

Status StageFileWriter::write(std::span<const uint8_t> bytes) {
  mCrc = crc32Continue(mCrc, bytes);
  mBytes += bytes.size();
  return mFile.write(bytes);
}

Status StageFileWriter::commit() {
  if (Status s = mFile.writeAt(0, stageHeader(mKind, mBytes, mBytes, mCrc)); !s) return s;
  return mFile.commit(AtomicFile::Durability::kUnsynced);
}

void OrderedStageWriter::put(size_t index, std::vector<uint8_t> piece) {
  std::lock_guard lock(mMutex);
  if (mFailure) return;
  mWaiting.emplace(index, std::move(piece));
  for (auto next = mWaiting.begin(); next != mWaiting.end() && next->first == mNext;
       next = mWaiting.erase(next), ++mNext)
    if (Status s = mFile.write(next->second); !s) {
      mFailure = s.error();
      return;
    }
}

Status OrderedStageWriter::commit(size_t count) {
  std::lock_guard lock(mMutex);
  if (mFailure) return *mFailure;
  if (mNext != count || !mWaiting.empty())
    return Error{"internal error: a stage file's pieces came " + std::to_string(mNext) + " of " +
                 std::to_string(count)};
  return mFile.commit();
}

Result<StageFileReader> StageFileReader::open(const std::string& path, StageFile kind) {
  if (!storedRaw(kind)) return Error{"internal error: only stored-raw stage files are streamed"};
  auto in = std::make_unique<std::ifstream>(path, std::ios::binary);
  auto h = openStageFile(path, kind, *in);
  if (!h) return h.error();
  return StageFileReader(path, std::move(in), h->packedBytes, h->crc);
}

std::optional<std::span<const uint8_t>> StageFileReader::read(size_t n) {
  if (n > mLeft) return std::nullopt;
  if (mBuffer.size() < n) mBuffer.resize(n);
  if (!readInto(mBuffer.data(), n)) return std::nullopt;
  return std::span<const uint8_t>(mBuffer.data(), n);
}

bool StageFileReader::readInto(void* to, size_t n) {
  if (n > mLeft) return false;
  if (!mIn->read(static_cast<char*>(to), std::streamsize(n))) {
    mLeft = 0;
    return false;
  }
  mLeft -= n;
  mCrc = crc32Continue(mCrc, {static_cast<const uint8_t*>(to), n});
  return true;
}

Status StageFileReader::finish() {
  if (mLeft != 0) return makeError(mPath, "damaged (records do not add up)");
  if (mCrc != mExpectedCrc) return makeError(mPath, "damaged (size or checksum does not match)");
  return {};
}

TextureSpool::TextureSpool() : mFile(std::tmpfile()) {
  if (!mFile)
    mFailure = Error{std::string("cannot make a temporary file: ") + std::strerror(errno)};
}

TextureSpool::~TextureSpool() {
  if (mFile) std::fclose(mFile);
}

void TextureSpool::add(uint32_t node, std::span<const uint8_t> blob) {
  std::lock_guard lock(mMutex);
  if (mFailure) return;
  if (std::fwrite(blob.data(), 1, blob.size(), mFile) != blob.size()) {
    mFailure = Error{std::string("cannot write a temporary file: ") + std::strerror(errno)};
    return;
  }
  mEntries.push_back({node, mEnd, blob.size()});
  mEnd += blob.size();
}

Status TextureSpool::writeSorted(const std::string& path) {
  std::lock_guard lock(mMutex);
  if (mFailure) return makeError(path, mFailure->message);
  if (std::fflush(mFile) != 0)
    return makeError(path, std::string("cannot write a temporary file: ") + std::strerror(errno));
  std::sort(mEntries.begin(), mEntries.end(),
            [](const Entry& a, const Entry& b) { return a.node < b.node; });
  auto out = StageFileWriter::create(path, StageFile::kJobTextures);
  if (!out) return out.error();
  auto put = [&](auto value) {
    uint8_t bytes[sizeof(value)];
    ByteWriter(bytes).put(value);
    return out->write(bytes);
  };
  if (Status s = put(uint64_t(mEntries.size())); !s) return s;
  std::vector<uint8_t> blob;
  for (const Entry& e : mEntries) {
    blob.resize(size_t(e.bytes));
    if (fseeko(mFile, off_t(e.offset), SEEK_SET) != 0 ||
        std::fread(blob.data(), 1, blob.size(), mFile) != blob.size())
      return makeError(path, "cannot read back a temporary file");
    if (Status s = put(e.node); !s) return s;
    if (Status s = put(uint64_t(e.bytes)); !s) return s;
    if (Status s = out->write(blob); !s) return s;
  }
  return out->commit();
}

}  // namespace terralod
