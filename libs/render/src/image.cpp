#include "terralod/render/image.h"

#include <stb_image.h>
#include <stb_image_write.h>

#include <cassert>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <span>

#include "terralod/core/atomic_file.h"

// Debian's libstb ships the stb implementations compiled (libstb.so), so no
// STB_*_IMPLEMENTATION here.

namespace terralod {
namespace {

constexpr uint8_t kPngSignature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};

void appendBytes(void* context, void* data, int size) {
  auto* bytes = static_cast<std::vector<uint8_t>*>(context);
  const auto* begin = static_cast<const uint8_t*>(data);
  bytes->insert(bytes->end(), begin, begin + size);
}

}  // namespace

std::array<uint8_t, 4> Image::pixel(int x, int y) const {
  assert(x >= 0 && x < width && y >= 0 && y < height);
  const uint8_t* p = rgba.data() + (size_t(y) * size_t(width) + size_t(x)) * 4;
  return {p[0], p[1], p[2], p[3]};
}

namespace {

// Encodes in memory first (so a failed encode never touches the file system), then writes the
// file atomically.
template <typename Encode>
Status writeEncoded(const Image& image, const std::string& path, const char* format,
                    Encode&& encode) {
  if (image.width < 1 || image.height < 1)
    return makeError(path, "cannot write an empty image (" + std::to_string(image.width) + "x" +
                               std::to_string(image.height) + ")");
  assert(image.rgba.size() == size_t(image.width) * size_t(image.height) * 4);
  std::vector<uint8_t> bytes;
  if (!encode(bytes)) return makeError(path, std::string(format) + " encoding failed");
  auto file = AtomicFile::create(path);
  if (!file) return file.error();
  if (Status s = file->write(std::span<const uint8_t>(bytes)); !s) return s;
  return file->commit();
}

}  // namespace

Status writePng(const Image& image, const std::string& path) {
  return writeEncoded(image, path, "PNG", [&](std::vector<uint8_t>& png) {
    return stbi_write_png_to_func(appendBytes, &png, image.width, image.height, 4,
                                  image.rgba.data(), image.width * 4) != 0;
  });
}

Status writeJpeg(const Image& image, const std::string& path, int quality) {
  return writeEncoded(image, path, "JPEG", [&](std::vector<uint8_t>& jpeg) {
    return stbi_write_jpg_to_func(appendBytes, &jpeg, image.width, image.height, 4,
                                  image.rgba.data(), quality) != 0;
  });
}

Result<ImageFormat> imageFormatFor(const std::string& path) {
  const std::string extension = std::filesystem::path(path).extension().string();
  std::string lower;
  for (const char ch : extension) lower += char(std::tolower(static_cast<unsigned char>(ch)));
  if (lower == ".png") return ImageFormat::kPng;
  if (lower == ".jpg" || lower == ".jpeg") return ImageFormat::kJpeg;
  return makeError(path, (extension.empty() ? std::string("no image type in the name")
                                            : "cannot write " + extension + " images") +
                             ": name it .png, .jpg or .jpeg");
}

Status writeImage(const Image& image, const std::string& path) {
  auto format = imageFormatFor(path);
  if (!format) return format.error();
  return *format == ImageFormat::kJpeg ? writeJpeg(image, path, 90) : writePng(image, path);
}

Result<Image> readPng(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return makeError(path, std::string("cannot open: ") + std::strerror(errno));
  const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                   std::istreambuf_iterator<char>());
  if (in.bad()) return makeError(path, "read failed");
  if (bytes.size() < sizeof(kPngSignature) ||
      std::memcmp(bytes.data(), kPngSignature, sizeof(kPngSignature)) != 0)
    return makeError(path, "not a PNG file");
  int width = 0, height = 0, channels = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes.data(), int(bytes.size()), &width, &height, &channels, 4),
      stbi_image_free);
  if (!pixels)
    return makeError(path, std::string("cannot decode PNG (") + stbi_failure_reason() + ")");
  Image image;
  image.width = width;
  image.height = height;
  image.rgba.assign(pixels.get(), pixels.get() + size_t(width) * size_t(height) * 4);
  return image;
}

}  // namespace terralod
