#include "terralod/format/byte_source.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace terralod {
namespace {

class FileSource final : public ByteSource {
 public:
  FileSource(int fd, uint64_t size, std::string path)
      : mFd(fd), mSize(size), mPath(std::move(path)) {}
  ~FileSource() override { ::close(mFd); }
  uint64_t size() const override { return mSize; }
  const std::string& name() const override { return mPath; }
  Result<std::vector<uint8_t>> read(uint64_t offset, uint64_t length) const override {
    if (offset > mSize || length > mSize - offset)
      return makeError(mPath, "read of " + std::to_string(length) + " bytes at offset " +
                                  std::to_string(offset) + " is past the end of the file (" +
                                  std::to_string(mSize) + " bytes)");
    std::vector<uint8_t> bytes(length);
    uint64_t done = 0;
    while (done < length) {
      const ssize_t n = ::pread(mFd, bytes.data() + done, length - done, off_t(offset + done));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0)
        return makeError(mPath, n == 0 ? "file shrank while reading" : std::strerror(errno));
      done += uint64_t(n);
    }
    return bytes;
  }

 private:
  int mFd;
  uint64_t mSize;
  std::string mPath;
};

class MemorySource final : public ByteSource {
 public:
  MemorySource(std::vector<uint8_t> bytes, std::string name)
      : mBytes(std::move(bytes)), mName(std::move(name)) {}
  uint64_t size() const override { return mBytes.size(); }
  const std::string& name() const override { return mName; }
  Result<std::vector<uint8_t>> read(uint64_t offset, uint64_t length) const override {
    if (offset > mBytes.size() || length > mBytes.size() - offset)
      return makeError(mName, "read past the end of the data");
    return std::vector<uint8_t>(mBytes.begin() + offset, mBytes.begin() + offset + length);
  }

 private:
  std::vector<uint8_t> mBytes;
  std::string mName;
};

}  // namespace

Result<std::unique_ptr<ByteSource>> openFileSource(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return makeError(path, errno == ENOENT ? "no such file" : std::strerror(errno));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    return makeError(path, "not a regular file");
  }
  return std::unique_ptr<ByteSource>(new FileSource(fd, uint64_t(st.st_size), path));
}

std::unique_ptr<ByteSource> makeMemorySource(std::vector<uint8_t> bytes, std::string name) {
  return std::make_unique<MemorySource>(std::move(bytes), std::move(name));
}

}  // namespace terralod
