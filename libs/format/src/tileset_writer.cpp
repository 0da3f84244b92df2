#include "terralod/format/tileset_writer.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>

namespace terralod {
namespace {
constexpr size_t kBufferBytes = 4 << 20;
}

TilesetWriter::TilesetWriter(std::string path, std::string tempPath, int fd)
    : mPath(std::move(path)), mTempPath(std::move(tempPath)), mFd(fd) {
  mBuffer.reserve(kBufferBytes);
}

TilesetWriter::~TilesetWriter() {
  if (mFd >= 0) ::close(mFd);
  if (!mFinished) ::unlink(mTempPath.c_str());
}

Result<std::unique_ptr<TilesetWriter>> TilesetWriter::create(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec))
    return makeError(path, "is a directory; give a file name for the tileset");
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    return makeError(path, "cannot write: directory " + dir.string() + " does not exist");
  std::string temp = (dir / ("." + target.filename().string() + ".partial-XXXXXX")).string();
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) return makeError(path, std::string("cannot write: ") + std::strerror(errno));
  ::fchmod(fd, 0644);  // mkstemp's 0600 would hide the tileset from web servers and other users
  auto writer = std::unique_ptr<TilesetWriter>(new TilesetWriter(path, temp, fd));
  // A zero header marks the file as incomplete until finish().
  const std::vector<uint8_t> zeros(kHeaderBytes, 0);
  if (Status s = writer->writeAll(zeros.data(), zeros.size()); !s) return s.error();
  return writer;
}

Status TilesetWriter::writeAll(const uint8_t* data, size_t size) {
  if (mBuffer.size() + size > kBufferBytes)
    if (Status s = flush(); !s) return s;
  if (size >= kBufferBytes) {
    size_t done = 0;
    while (done < size) {
      const ssize_t n = ::write(mFd, data + done, size - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) return makeError(mPath, std::string("write failed: ") + std::strerror(errno));
      done += size_t(n);
    }
  } else {
    mBuffer.insert(mBuffer.end(), data, data + size);
  }
  mOffset += size;
  return {};
}

Status TilesetWriter::flush() {
  size_t done = 0;
  while (done < mBuffer.size()) {
    const ssize_t n = ::write(mFd, mBuffer.data() + done, mBuffer.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return makeError(mPath, std::string("write failed: ") + std::strerror(errno));
    done += size_t(n);
  }
  mBuffer.clear();
  return {};
}

Result<uint64_t> TilesetWriter::appendBlob(std::span<const uint8_t> bytes) {
  const uint64_t offset = mOffset;
  if (Status s = writeAll(bytes.data(), bytes.size()); !s) return s.error();
  return offset;
}

Status TilesetWriter::finish(TilesetHeader header, const std::vector<NodeRecord>& nodes,
                             const std::string& metadata) {
  std::vector<uint8_t> table(nodes.size() * kNodeRecordBytes);
  for (size_t i = 0; i < nodes.size(); ++i)
    serializeNode(nodes[i], table.data() + i * kNodeRecordBytes);
  header.nodeCount = nodes.size();
  header.nodeTableOffset = mOffset;
  header.nodeTableBytes = table.size();
  header.nodeTableCrc = crc32Of(table);
  if (Status s = writeAll(table.data(), table.size()); !s) return s;
  header.metadataOffset = mOffset;
  header.metadataBytes = metadata.size();
  header.metadataCrc =
      crc32Of(std::span(reinterpret_cast<const uint8_t*>(metadata.data()), metadata.size()));
  if (Status s = writeAll(reinterpret_cast<const uint8_t*>(metadata.data()), metadata.size()); !s)
    return s;
  header.fileBytes = mOffset;
  if (Status s = flush(); !s) return s;
  const std::vector<uint8_t> headerBytes = serializeHeader(header);
  for (size_t done = 0; done < headerBytes.size();) {
    const ssize_t n =
        ::pwrite(mFd, headerBytes.data() + done, headerBytes.size() - done, off_t(done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return makeError(mPath, std::string("write failed: ") + std::strerror(errno));
    done += size_t(n);
  }
  if (::fsync(mFd) != 0)
    return makeError(mPath, std::string("sync failed: ") + std::strerror(errno));
  ::close(mFd);
  mFd = -1;
  if (::rename(mTempPath.c_str(), mPath.c_str()) != 0)
    return makeError(mPath, std::string("cannot replace: ") + std::strerror(errno));
  mFinished = true;
  // The rename is durable once the directory is synced; a failure here loses nothing.
  const std::filesystem::path parent = std::filesystem::path(mPath).parent_path();
  const int dir = ::open(parent.empty() ? "." : parent.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
  return {};
}

}  // namespace terralod
