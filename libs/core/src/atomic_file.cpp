#include "terralod/core/atomic_file.h"

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

AtomicFile::AtomicFile(std::string path, std::string tempPath, int fd)
    : mPath(std::move(path)), mTempPath(std::move(tempPath)), mFd(fd) {
  mBuffer.reserve(kBufferBytes);
}

AtomicFile::AtomicFile(AtomicFile&& other) noexcept
    : mPath(std::move(other.mPath)),
      mTempPath(std::move(other.mTempPath)),
      mFd(other.mFd),
      mBytes(other.mBytes),
      mBuffer(std::move(other.mBuffer)),
      mCommitted(other.mCommitted) {
  // The moved-from object must neither close the descriptor nor unlink the file.
  other.mFd = -1;
  other.mCommitted = true;
}

AtomicFile::~AtomicFile() {
  if (mFd >= 0) ::close(mFd);
  if (!mCommitted) ::unlink(mTempPath.c_str());
}

Result<AtomicFile> AtomicFile::create(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec)) return makeError(path, "is a directory; give a file name");
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    return makeError(path, "cannot write: directory " + dir.string() + " does not exist");
  std::string temp = (dir / ("." + target.filename().string() + ".partial-XXXXXX")).string();
  const int fd = ::mkstemp(temp.data());
  if (fd < 0) return makeError(path, std::string("cannot write: ") + std::strerror(errno));
  ::fchmod(fd, 0644);  // mkstemp's 0600 would hide the file from other users
  return AtomicFile(path, temp, fd);
}

Status AtomicFile::write(std::span<const uint8_t> bytes) {
  if (mBuffer.size() + bytes.size() > kBufferBytes)
    if (Status s = flush(); !s) return s;
  mBytes += bytes.size();
  if (bytes.size() < kBufferBytes) {
    mBuffer.insert(mBuffer.end(), bytes.begin(), bytes.end());
    return {};
  }
  return writeAll(bytes.data(), bytes.size());  // large writes skip the buffer
}

Status AtomicFile::flush() {
  Status s = writeAll(mBuffer.data(), mBuffer.size());
  mBuffer.clear();
  return s;
}

Status AtomicFile::writeAll(const uint8_t* data, size_t size) {
  size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(mFd, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return makeError(mPath, std::string("write failed: ") + std::strerror(errno));
    done += size_t(n);
  }
  return {};
}

Status AtomicFile::writeAt(uint64_t offset, std::span<const uint8_t> bytes) {
  if (Status s = flush(); !s) return s;
  for (size_t done = 0; done < bytes.size();) {
    const ssize_t n = ::pwrite(mFd, bytes.data() + done, bytes.size() - done, off_t(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return makeError(mPath, std::string("write failed: ") + std::strerror(errno));
    done += size_t(n);
  }
  return {};
}

Status AtomicFile::commit() {
  if (Status s = flush(); !s) return s;
  if (::fsync(mFd) != 0)
    return makeError(mPath, std::string("sync failed: ") + std::strerror(errno));
  ::close(mFd);
  mFd = -1;
  if (::rename(mTempPath.c_str(), mPath.c_str()) != 0)
    return makeError(mPath, std::string("cannot replace: ") + std::strerror(errno));
  mCommitted = true;
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
