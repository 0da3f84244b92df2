#pragma once
// Little-endian field packing for the frozen file formats (tilesets, chunk and texture blobs,
// vegetation files): explicit, never struct memcpy. Callers size buffers and check lengths.

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <span>
#include <type_traits>
#include <vector>

namespace terralod {

class ByteWriter {
 public:
  explicit ByteWriter(uint8_t* out) : mOut(out) {}
  template <typename T>
  void put(T value) {
    static_assert(std::is_arithmetic_v<T>);
    uint8_t bytes[sizeof(T)];
    std::memcpy(bytes, &value, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
    std::memcpy(mOut + mPos, bytes, sizeof(T));
    mPos += sizeof(T);
  }
  void putBytes(const void* data, size_t n) {
    std::memcpy(mOut + mPos, data, n);
    mPos += n;
  }
  void seek(size_t pos) { mPos = pos; }
  size_t position() const { return mPos; }

 private:
  uint8_t* mOut;
  size_t mPos = 0;
};

class ByteReader {
 public:
  explicit ByteReader(const uint8_t* in) : mIn(in) {}
  template <typename T>
  T get() {
    static_assert(std::is_arithmetic_v<T>);
    uint8_t bytes[sizeof(T)];
    std::memcpy(bytes, mIn + mPos, sizeof(T));
    if constexpr (std::endian::native == std::endian::big) std::reverse(bytes, bytes + sizeof(T));
    T value;
    std::memcpy(&value, bytes, sizeof(T));
    mPos += sizeof(T);
    return value;
  }
  void getBytes(void* out, size_t n) {
    std::memcpy(out, mIn + mPos, n);
    mPos += n;
  }
  void skip(size_t n) { mPos += n; }
  void seek(size_t pos) { mPos = pos; }
  size_t position() const { return mPos; }

 private:
  const uint8_t* mIn;
  size_t mPos = 0;
};

}  // namespace terralod
