#pragma once
// The files a staged build's jobs hand each other in the work directory (docs/format.md,
// "Staged build work directory"): a small header (magic, kind, sizes, CRC-32) over a zstd
// payload of little-endian fields. They live only as long as one build, but a job killed
// mid-write, a full disk or a file from another build must still be told apart from a good
// one: files are written atomically and checked on reading.

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "terralod/core/atomic_file.h"
#include "terralod/core/result.h"
#include "terralod/format/byte_io.h"

namespace terralod {

enum class StageFile : uint32_t {
  // 1, 2, 3 and 5 held one block's pass-1 halo, grid, reduced halo and coarse points, a file
  // per block; 10 to 13 hold the same for all of a job's blocks.
  kCoarsePoints = 4,  ///< the height range, and halo points the coarse levels use
  // 6 held what 14 holds after a u64 count (which a job cannot know before its last block)
  // 7 held one block node's float texture tiles (before job frontiers)
  kJobTiles = 8,     ///< a block job's frontier: nodes' float texture tiles (stored as they are)
  kJobTextures = 9,  ///< the texture blobs of a block job's block nodes and the nodes it built
  // One record per block of a job (writeBlockRecords):
  kPass1Halos = 10,    ///< halo values, square errors, heights on the block lines, range
  kPass1Grids = 11,    ///< activations (closed square, borders one-sided), a zstd frame each
  kReducedHalos = 12,  ///< finished halo values
  kBlockCoarse = 13,   ///< what the coarse levels need of a block (points)
  kChunks = 14,        ///< built chunks with their node records, to the end (stored as they are)
  kKeptHeights = 15,   ///< the heights pass 2 reads (KeptHeights' bits, values), a zstd frame each
  /// The texture blobs of the chunks below a job's block nodes, in its chunk file's order, to
  /// the end (stored as they are): pass 1 makes them, assemble reads them in step.
  kChunkTextures = 16,
};

/// Kinds whose payload is already compressed or is floats zstd barely shrinks: stored raw.
inline bool storedRaw(StageFile kind) {
  return kind == StageFile::kChunks || kind == StageFile::kJobTiles ||
         kind == StageFile::kJobTextures || kind == StageFile::kPass1Grids ||
         kind == StageFile::kChunkTextures || kind == StageFile::kKeptHeights;
}

/// Growable little-endian writer.
class Packer {
 public:
  template <typename T>
  void put(T value) {
    const size_t at = mBytes.size();
    mBytes.resize(at + sizeof(T));
    ByteWriter(mBytes.data() + at).put(value);
  }
  void putBytes(std::span<const uint8_t> bytes) {
    put<uint64_t>(bytes.size());
    mBytes.insert(mBytes.end(), bytes.begin(), bytes.end());
  }
  template <typename T>
  void putArray(const std::vector<T>& values) {
    put<uint64_t>(values.size());
    if constexpr (std::endian::native == std::endian::little) {
      const auto* first = reinterpret_cast<const uint8_t*>(values.data());
      mBytes.insert(mBytes.end(), first, first + values.size() * sizeof(T));
    } else {
      for (const T& v : values) put(v);
    }
  }
  /// A u64 count, then each (u64 key, value).
  template <typename V>
  void putKeyed(const std::vector<std::pair<uint64_t, V>>& entries) {
    put<uint64_t>(entries.size());
    for (const auto& [key, value] : entries) {
      put(key);
      put(value);
    }
  }
  /// Room for `bytes` more, so that large payloads are not moved as they grow.
  void reserve(size_t bytes) { mBytes.reserve(mBytes.size() + bytes); }
  std::vector<uint8_t>& bytes() { return mBytes; }

 private:
  std::vector<uint8_t> mBytes;
};

/// Bounds-checked reader: past the end it returns zeros and ok() turns false.
class Unpacker {
 public:
  explicit Unpacker(std::span<const uint8_t> bytes) : mBytes(bytes) {}
  template <typename T>
  T get() {
    if (!mOk || mBytes.size() - mPos < sizeof(T)) {
      mOk = false;
      return T{};
    }
    ByteReader r(mBytes.data() + mPos);
    mPos += sizeof(T);
    return r.get<T>();
  }
  /// A byte string, viewed in place (valid while the payload is).
  std::span<const uint8_t> getView() {
    const uint64_t n = get<uint64_t>();
    if (!mOk || mBytes.size() - mPos < n) {
      mOk = false;
      return {};
    }
    const std::span<const uint8_t> out = mBytes.subspan(mPos, n);
    mPos += n;
    return out;
  }
  std::vector<uint8_t> getBytes() {
    const std::span<const uint8_t> view = getView();
    return std::vector<uint8_t>(view.begin(), view.end());
  }
  template <typename T>
  std::vector<T> getArray() {
    const uint64_t n = get<uint64_t>();
    if (!mOk || (mBytes.size() - mPos) / sizeof(T) < n) {
      mOk = false;
      return {};
    }
    std::vector<T> out(n);
    if constexpr (std::endian::native == std::endian::little) {
      if (n) std::memcpy(out.data(), mBytes.data() + mPos, n * sizeof(T));
      mPos += n * sizeof(T);
    } else {
      for (T& v : out) v = get<T>();
    }
    return out;
  }
  /// What putKeyed wrote.
  template <typename V>
  std::vector<std::pair<uint64_t, V>> getKeyed() {
    const uint64_t n = get<uint64_t>();
    std::vector<std::pair<uint64_t, V>> out;
    for (uint64_t i = 0; mOk && i < n; ++i) {
      const uint64_t key = get<uint64_t>();
      out.emplace_back(key, get<V>());
    }
    return out;
  }
  bool ok() const { return mOk; }
  bool atEnd() const { return mPos == mBytes.size(); }

 private:
  std::span<const uint8_t> mBytes;
  size_t mPos = 0;
  bool mOk = true;
};

Status writeStageFile(const std::string& path, StageFile kind, std::span<const uint8_t> payload);

/// A stage file's payload (read without first zeroing a buffer its size: these are gigabytes).
class StagePayload {
 public:
  StagePayload(std::unique_ptr<uint8_t[]> data, size_t size)
      : mData(std::move(data)), mSize(size) {}
  std::span<const uint8_t> bytes() const { return {mData.get(), mSize}; }

 private:
  std::unique_ptr<uint8_t[]> mData;
  size_t mSize;
};

/// Errors name the file ("missing", "not a stage file", "damaged").
Result<StagePayload> readStageFile(const std::string& path, StageFile kind);

/// A job's per-block results in one file, in the job's block order: u64 count, then a byte
/// string per block. (One file per block made a pass-1 task create 128 files, and a build
/// five per block: ext4 spends much of a small task allocating their inodes, and cluster file
/// systems are slower still at many small files.)
Status writeBlockRecords(const std::string& path, StageFile kind,
                         const std::vector<std::vector<uint8_t>>& records);

/// A record compressed on its own (a zstd frame), for a job's records too large to hold
/// uncompressed together: its blocks' activation grids (8 MB for 64 blocks of 512 cells).
std::vector<uint8_t> compressedRecord(std::span<const uint8_t> raw);
/// Decompresses a compressedRecord into `out`, which must be exactly its size (else the file
/// is "written for another block layout"); errors name `path`.
Status decompressRecord(std::span<const uint8_t> record, std::span<uint8_t> out,
                        const std::string& path);

/// A compressedRecord of at most `maxBytes` (more is "written for another block layout").
Result<std::vector<uint8_t>> decompressRecord(std::span<const uint8_t> record, size_t maxBytes,
                                              const std::string& path);

/// What writeBlockRecords wrote, viewed in place; a count other than `blocks` is "written for
/// another block layout".
class BlockRecords {
 public:
  static Result<BlockRecords> read(const std::string& path, StageFile kind, size_t blocks);
  std::span<const uint8_t> operator[](size_t i) const { return mRecords[i]; }
  size_t size() const { return mRecords.size(); }

 private:
  explicit BlockRecords(StagePayload payload) : mPayload(std::move(payload)) {}
  StagePayload mPayload;
  std::vector<std::span<const uint8_t>> mRecords;
};

/// A stored-raw stage file written a piece at a time, for payloads not worth holding whole;
/// the same bytes as writeStageFile of the pieces joined.
class StageFileWriter {
 public:
  static Result<StageFileWriter> create(const std::string& path, StageFile kind);
  Status write(std::span<const uint8_t> bytes);
  /// Fills in the header and puts the file in place.
  Status commit();

 private:
  StageFileWriter(AtomicFile file, StageFile kind) : mFile(std::move(file)), mKind(kind) {}
  AtomicFile mFile;
  StageFile mKind;
  uint64_t mBytes = 0;
  uint32_t mCrc = 0;
};

/// A stored-raw stage file made of pieces numbered 0, 1, 2, ... that come in any order (from
/// threads, each its own): each is written as soon as those before it are, so only pieces
/// that come early wait in memory, not the whole file.
class OrderedStageWriter {
 public:
  explicit OrderedStageWriter(StageFileWriter file) : mFile(std::move(file)) {}
  /// Thread-safe. A failure is kept and returned by commit().
  void put(size_t index, std::vector<uint8_t> piece);
  /// Fails unless pieces 0 .. count - 1 were all given.
  Status commit(size_t count);

 private:
  std::mutex mMutex;
  StageFileWriter mFile;
  size_t mNext = 0;
  std::map<size_t, std::vector<uint8_t>> mWaiting;
  std::optional<Error> mFailure;
};

/// A stored-raw stage file read a piece at a time. Its checksum covers the whole payload, so
/// finish() says whether what was read can be trusted; use nothing read before it succeeds
/// for anything that cannot be undone.
class StageFileReader {
 public:
  static Result<StageFileReader> open(const std::string& path, StageFile kind);
  /// Little-endian values, as Unpacker reads them; nullopt past the payload's end.
  template <typename T>
  std::optional<T> get() {
    auto b = read(sizeof(T));
    if (!b) return std::nullopt;
    return ByteReader(b->data()).get<T>();
  }
  /// A byte string (u64 length, then its bytes), valid until the next read.
  std::optional<std::span<const uint8_t>> getView() {
    auto n = get<uint64_t>();
    if (!n) return std::nullopt;
    return read(size_t(*n));
  }
  /// An array (u64 count, then the values), as Unpacker::getArray reads it, read straight
  /// into its vector; nullopt past the payload's end.
  template <typename T>
  std::optional<std::vector<T>> getArray() {
    auto n = get<uint64_t>();
    if (!n || *n > mLeft / sizeof(T)) return std::nullopt;
    std::vector<T> out(static_cast<size_t>(*n));
    if constexpr (std::endian::native == std::endian::little) {
      if (!readInto(out.data(), out.size() * sizeof(T))) return std::nullopt;
    } else {
      for (T& v : out) {
        auto x = get<T>();
        if (!x) return std::nullopt;
        v = *x;
      }
    }
    return out;
  }
  /// Whether every byte of the payload has been read.
  bool atEnd() const { return mLeft == 0; }
  /// Whether the payload was read to its end, and its checksum matches.
  Status finish();
  const std::string& path() const { return mPath; }

 private:
  StageFileReader(std::string path, std::unique_ptr<std::ifstream> in, uint64_t bytes, uint32_t crc)
      : mPath(std::move(path)), mIn(std::move(in)), mLeft(bytes), mExpectedCrc(crc) {}
  std::optional<std::span<const uint8_t>> read(size_t n);
  bool readInto(void* to, size_t n);

  std::string mPath;
  std::unique_ptr<std::ifstream> mIn;
  uint64_t mLeft;
  uint32_t mExpectedCrc, mCrc = 0;
  std::vector<uint8_t> mBuffer;
};

/// Texture blobs as a block job makes them, in any order, kept in an unnamed temporary file
/// (gone when the job ends, however it ends) instead of in memory, and written out in node
/// order as a kJobTextures stage file (u64 count, then each: u32 node, u64 size, the blob).
class TextureSpool {
 public:
  TextureSpool();
  ~TextureSpool();
  TextureSpool(const TextureSpool&) = delete;
  TextureSpool& operator=(const TextureSpool&) = delete;
  /// Thread-safe. A failure (a full disk) is kept and returned by writeSorted.
  void add(uint32_t node, std::span<const uint8_t> blob);
  Status writeSorted(const std::string& path);

 private:
  struct Entry {
    uint32_t node;
    uint64_t offset, bytes;
  };
  std::mutex mMutex;
  std::FILE* mFile = nullptr;
  uint64_t mEnd = 0;
  std::vector<Entry> mEntries;
  std::optional<Error> mFailure;
};

}  // namespace terralod
