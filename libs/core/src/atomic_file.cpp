#include "terralod/core/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <random>

namespace terralod {
namespace {

constexpr size_t kBufferBytes = 4 << 20;

std::string hiddenTempPrefix(const std::filesystem::path& dir,
                             const std::filesystem::path& target) {
  return (dir / ("." + target.filename().string() + ".partial-")).string();
}

}  // namespace

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
  if (mFd >= 0) ::close(mFd);  // an unnamed temporary file vanishes with its descriptor
  if (!mCommitted && !mTempPath.empty()) ::unlink(mTempPath.c_str());
}

Result<AtomicFile> AtomicFile::create(const std::string& path, Temporary temporary) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::error_code ec;
  if (fs::is_directory(target, ec)) return makeError(path, "is a directory; give a file name");
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir, ec))
    return makeError(path, "cannot write: directory " + dir.string() + " does not exist");
  // commit() names an unnamed file through /proc/self/fd, so without /proc it cannot be used.
  if (temporary == Temporary::kUnnamedIfPossible && ::access("/proc/self/fd", X_OK) == 0) {
    const int fd = ::open(dir.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0644);
    if (fd >= 0) {
      ::fchmod(fd, 0644);  // as a named file would get, whatever the umask
      return AtomicFile(path, "", fd);
    }
    // Not supported by this file system (or kernel): fall back to a named file; anything
    // else (permissions, a full disk) fails the same way there.
  }
  std::string temp = hiddenTempPrefix(dir, target) + "XXXXXX";
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

Status AtomicFile::commit(Durability durability) {
  if (Status s = flush(); !s) return s;
  if (durability == Durability::kSynced && ::fsync(mFd) != 0)
    return makeError(mPath, std::string("sync failed: ") + std::strerror(errno));
  if (mTempPath.empty()) {
    if (Status s = linkIntoPlace(); !s) return s;
  } else if (::rename(mTempPath.c_str(), mPath.c_str()) != 0) {
    return makeError(mPath, std::string("cannot replace: ") + std::strerror(errno));
  }
  ::close(mFd);
  mFd = -1;
  mCommitted = true;
  if (durability == Durability::kUnsynced) return {};
  // The new name is durable once the directory is synced; a failure here loses nothing.
  const std::filesystem::path parent = std::filesystem::path(mPath).parent_path();
  const int dir = ::open(parent.empty() ? "." : parent.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir >= 0) {
    ::fsync(dir);
    ::close(dir);
  }
  return {};
}

// An unnamed file gets its name from linkat() through /proc/self/fd. link() never replaces a
// file, so over an existing target it gets a hidden name first and is renamed over the
// target: the only moment a complete file has another name is between those two calls.
Status AtomicFile::linkIntoPlace() {
  const std::string self = "/proc/self/fd/" + std::to_string(mFd);
  auto link = [&](const std::string& to) {
    return ::linkat(AT_FDCWD, self.c_str(), AT_FDCWD, to.c_str(), AT_SYMLINK_FOLLOW) == 0;
  };
  if (link(mPath)) return {};
  if (errno != EEXIST)
    return makeError(mPath, std::string("cannot create: ") + std::strerror(errno));
  const std::filesystem::path target(mPath);
  const std::string prefix =
      hiddenTempPrefix(target.has_parent_path() ? target.parent_path() : ".", target);
  std::random_device random;
  for (int attempt = 0; attempt < 100; ++attempt) {
    const std::string temp = prefix + std::to_string(random());
    if (!link(temp)) {
      if (errno == EEXIST) continue;
      return makeError(mPath, std::string("cannot replace: ") + std::strerror(errno));
    }
    if (::rename(temp.c_str(), mPath.c_str()) != 0) {
      const int error = errno;
      ::unlink(temp.c_str());
      return makeError(mPath, std::string("cannot replace: ") + std::strerror(error));
    }
    return {};
  }
  return makeError(mPath, "cannot replace: no free temporary name");
}

}  // namespace terralod
