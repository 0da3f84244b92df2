#include "terralod/render/texture_arrays.h"

#include <epoxy/gl.h>

#include <algorithm>

namespace terralod {
namespace {

// Colour is stored as display (gamma-encoded) values: the sRGB format makes the GPU linearise
// texels before filtering, so filtering and mip blending happen in linear light.
GLenum glFormat(TextureEncoding e) {
  return e == TextureEncoding::kBc1 ? GL_COMPRESSED_SRGB_S3TC_DXT1_EXT : GL_COMPRESSED_RG_RGTC2;
}

uint32_t makeArray(TextureEncoding encoding, uint32_t size, uint32_t levels, uint32_t layers) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t);
  glTextureStorage3D(t, GLsizei(levels), glFormat(encoding), GLsizei(size), GLsizei(size),
                     GLsizei(layers));
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  // Edge texels lie on the chunk border: clamping makes the border read exactly them.
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

}  // namespace

TextureArrays::~TextureArrays() {
  for (const Array& a : mArrays)
    if (a.texture) glDeleteTextures(1, &a.texture);
}

uint32_t TextureArrays::classFor(TextureEncoding encoding, uint32_t size) {
  auto [it, added] = mClasses.try_emplace({encoding, size}, uint32_t(mArrays.size()));
  if (added) {
    Array a;
    a.encoding = encoding;
    a.size = size;
    a.levels = mipCount(size);
    for (uint32_t m = 0; m < a.levels; ++m) a.layerBytes += mipBytes(encoding, size, m);
    mArrays.push_back(std::move(a));
  }
  return it->second;
}

void TextureArrays::grow(Array& a) {
  // Large layers grow slowly (a 4097² BC5 layer is 22 MB); small ones by doubling.
  const uint32_t more = std::max<uint32_t>(
      1, std::min<uint32_t>(std::max<uint32_t>(a.capacity, 8),
                            uint32_t(std::max<uint64_t>(1, (uint64_t{64} << 20) / a.layerBytes))));
  const uint32_t capacity = a.capacity + more;
  const uint32_t bigger = makeArray(a.encoding, a.size, a.levels, capacity);
  if (a.texture) {
    for (uint32_t m = 0; m < a.levels; ++m) {
      const GLsizei s = GLsizei(mipSize(a.size, m));
      glCopyImageSubData(a.texture, GL_TEXTURE_2D_ARRAY, GLint(m), 0, 0, 0, bigger,
                         GL_TEXTURE_2D_ARRAY, GLint(m), 0, 0, 0, s, s, GLsizei(a.capacity));
    }
    glDeleteTextures(1, &a.texture);
  }
  for (uint32_t l = capacity; l-- > a.capacity;) a.freeLayers.push_back(l);
  a.texture = bigger;
  a.capacity = capacity;
}

TextureSlot TextureArrays::upload(const TextureLayer& layer) {
  const uint32_t index = classFor(layer.encoding, layer.size);
  Array& a = mArrays[index];
  if (a.freeLayers.empty()) grow(a);
  const uint32_t l = a.freeLayers.back();
  a.freeLayers.pop_back();
  for (uint32_t m = 0; m < a.levels; ++m) {
    const GLsizei s = GLsizei(mipSize(a.size, m));
    glCompressedTextureSubImage3D(a.texture, GLint(m), 0, 0, GLint(l), s, s, 1,
                                  glFormat(a.encoding), GLsizei(layer.mips[m].size()),
                                  layer.mips[m].data());
  }
  return {index, l, a.size, layer.flags};
}

void TextureArrays::release(const TextureSlot& slot) {
  mArrays[slot.array].freeLayers.push_back(slot.layer);
}

}  // namespace terralod
