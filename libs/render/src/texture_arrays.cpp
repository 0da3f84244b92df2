#include "terralod/render/texture_arrays.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cassert>
#include <functional>

namespace terralod {
namespace {

// Colour is stored as display (gamma-encoded) values: the sRGB format makes the GPU linearise
// texels before filtering, so filtering and mip blending happen in linear light.
uint32_t makeArray(TextureEncoding encoding, uint32_t size, uint32_t levels, uint32_t layers) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t);
  glTextureStorage3D(t, GLsizei(levels), chunkTextureFormat(encoding), GLsizei(size), GLsizei(size),
                     GLsizei(layers));
  setChunkTextureSampling(t);
  return t;
}

}  // namespace

uint32_t chunkTextureFormat(TextureEncoding e) {
  switch (e) {
    case TextureEncoding::kBc1:
      return GL_COMPRESSED_SRGB_S3TC_DXT1_EXT;
    case TextureEncoding::kBc4:
      return GL_COMPRESSED_RED_RGTC1;
    case TextureEncoding::kBc5:
      break;
  }
  return GL_COMPRESSED_RG_RGTC2;
}

void setChunkTextureSampling(uint32_t t) {
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  // Edge texels lie on the chunk border: clamping makes the border read exactly them.
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
}

TextureArrays::~TextureArrays() {
  for (const Page& p : mPages)
    if (p.texture) glDeleteTextures(1, &p.texture);
  // Pages the worker finished but nobody adopted (the worker stops before this).
  for (const Class& c : mClasses)
    if (c.pending && c.pending->done() && *c.pendingTexture)
      glDeleteTextures(1, c.pendingTexture.get());
}

size_t TextureArrays::pageCount() const {
  return size_t(
      std::count_if(mPages.begin(), mPages.end(), [](const Page& p) { return p.texture != 0; }));
}

uint32_t TextureArrays::classFor(TextureEncoding encoding, uint32_t size) {
  auto [it, added] = mClassIndex.try_emplace({encoding, size}, uint32_t(mClasses.size()));
  if (added) {
    Class c;
    c.encoding = encoding;
    c.size = size;
    c.levels = mipCount(size);
    for (uint32_t m = 0; m < c.levels; ++m) c.layerBytes += mipBytes(encoding, size, m);
    mClasses.push_back(std::move(c));
  }
  return it->second;
}

uint32_t TextureArrays::nextPageCapacity(uint32_t cls) {
  if (mMaxLayers == 0) {
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &mMaxLayers);
    mMaxLayers = std::max(mMaxLayers, 1);
  }
  const Class& c = mClasses[cls];
  // Twice the newest page (the first: a few layers), at most kPageBytes, at least one layer.
  const uint32_t last = c.pages.empty() ? kFirstPageLayers / 2 : mPages[c.pages.back()].capacity;
  const uint64_t byBytes = std::max<uint64_t>(1, kPageBytes / c.layerBytes);
  return uint32_t(std::max<uint64_t>(
      1, std::min<uint64_t>({uint64_t(last) * 2, byBytes, uint64_t(mMaxLayers)})));
}

uint32_t TextureArrays::addPage(uint32_t cls, uint32_t texture, uint32_t capacity) {
  Class& c = mClasses[cls];
  Page page;
  page.cls = cls;
  page.capacity = capacity;
  page.texture = texture;
  // Free layers are a min-heap: the lowest first, so pages fill from the front.
  for (uint32_t l = 0; l < capacity; ++l) page.freeLayers.push_back(l);
  mAllocatedBytes += c.layerBytes * capacity;
  c.freeLayers += capacity;
  uint32_t id = 0;
  if (!mFreePageIds.empty()) {
    id = mFreePageIds.back();
    mFreePageIds.pop_back();
    mPages[id] = std::move(page);
  } else {
    id = uint32_t(mPages.size());
    mPages.push_back(std::move(page));
  }
  c.pages.push_back(id);
  return id;
}

void TextureArrays::requestPage(uint32_t cls) {
  Class& c = mClasses[cls];
  if (!mWorker || c.pending) return;
  c.pendingCapacity = nextPageCapacity(cls);
  c.pendingTexture = std::make_shared<uint32_t>(0);
  c.pending = mWorker->post(
      [texture = c.pendingTexture, encoding = c.encoding, size = c.size, levels = c.levels,
       capacity = c.pendingCapacity] { *texture = makeArray(encoding, size, levels, capacity); });
}

void TextureArrays::poll() {
  for (uint32_t cls = 0; cls < mClasses.size(); ++cls) {
    Class& c = mClasses[cls];
    if (!c.pending || !c.pending->done()) continue;
    addPage(cls, *c.pendingTexture, c.pendingCapacity);
    c.pending.reset();
    c.pendingTexture.reset();
  }
}

bool TextureArrays::reserve(TextureEncoding encoding, uint32_t size) {
  const uint32_t cls = classFor(encoding, size);
  Class& c = mClasses[cls];
  // A class's first page is small: made here, at once.
  if (c.freeLayers > 0 || !mWorker || (c.pages.empty() && !c.pending)) return true;
  requestPage(cls);
  return false;
}

void TextureArrays::freePage(uint32_t id) {
  Page& p = mPages[id];
  Class& c = mClasses[p.cls];
  std::erase(c.pages, id);
  glDeleteTextures(1, &p.texture);
  mAllocatedBytes -= c.layerBytes * p.capacity;
  c.freeLayers -= p.capacity;
  p = Page{};
  mFreePageIds.push_back(id);
}

TextureSlot TextureArrays::upload(const TextureLayer& layer) {
  const uint32_t cls = classFor(layer.encoding, layer.size);
  // The oldest page with room, so that the newest pages empty first and can be freed.
  uint32_t id = UINT32_MAX;
  for (uint32_t p : mClasses[cls].pages)
    if (!mPages[p].freeLayers.empty()) {
      id = p;
      break;
    }
  if (id == UINT32_MAX) {
    const uint32_t capacity = nextPageCapacity(cls);
    const Class& c = mClasses[cls];
    id = addPage(cls, makeArray(c.encoding, c.size, c.levels, capacity), capacity);
  }
  Page& page = mPages[id];
  Class& c = mClasses[cls];
  std::pop_heap(page.freeLayers.begin(), page.freeLayers.end(), std::greater<>());
  const uint32_t l = page.freeLayers.back();
  page.freeLayers.pop_back();
  --c.freeLayers;
  for (uint32_t m = 0; m < c.levels; ++m) {
    const GLsizei s = GLsizei(mipSize(c.size, m));
    glCompressedTextureSubImage3D(page.texture, GLint(m), 0, 0, GLint(l), s, s, 1,
                                  chunkTextureFormat(c.encoding), GLsizei(layer.mips[m].size()),
                                  layer.mips[m].data());
  }
  // Running low: the next page is made ahead, off this thread.
  if (c.freeLayers < (mPages[c.pages.back()].capacity + 1) / 2) requestPage(cls);
  return {id, l, c.size, layer.flags};
}

void TextureArrays::release(const TextureSlot& slot) {
  Page& page = mPages[slot.array];
  assert(page.texture != 0);
  page.freeLayers.push_back(slot.layer);
  std::push_heap(page.freeLayers.begin(), page.freeLayers.end(), std::greater<>());
  Class& c = mClasses[page.cls];
  ++c.freeLayers;
  // An empty page goes, unless its class would then be short of room at once (the next upload
  // would ask for a page again).
  if (page.freeLayers.size() == page.capacity && c.pages.size() > 1 &&
      c.freeLayers - page.capacity >= page.capacity / 2)
    freePage(slot.array);
}

}  // namespace terralod
