// Chunk memory on the GPU: pages of array textures that never move (what is resident keeps
// its texels while pages come and go), empty pages given back, pages and larger geometry
// buffers made ahead of need on a worker context that shares the render context's objects.

#include "terralod/render/texture_arrays.h"

#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <thread>

#include "terralod/render/gl_context.h"
#include "terralod/render/gl_worker.h"
#include "terralod/render/gpu_chunk_store.h"

namespace terralod {
namespace {

constexpr uint32_t kSize = 9;  // 9, 4, 2, 1: 3 x 3, 1 x 1, 1, 1 blocks

// A BC5 layer whose bytes say which layer it is (any bytes are valid BC5).
TextureLayer layerWithSeed(uint32_t seed) {
  TextureLayer layer;
  layer.kind = TextureLayerKind::kNormal;
  layer.encoding = TextureEncoding::kBc5;
  layer.size = kSize;
  for (uint32_t m = 0; m < mipCount(kSize); ++m) {
    std::vector<uint8_t> bytes(mipBytes(layer.encoding, kSize, m));
    for (size_t i = 0; i < bytes.size(); ++i) bytes[i] = uint8_t(seed * 31 + i * 7 + m);
    layer.mips.push_back(std::move(bytes));
  }
  return layer;
}

// Mip 0 of one layer, read back from the GPU.
std::vector<uint8_t> readBack(const TextureArrays& arrays, const TextureSlot& slot) {
  std::vector<uint8_t> bytes(mipBytes(TextureEncoding::kBc5, kSize, 0));
  glGetCompressedTextureSubImage(arrays.arrayTexture(slot.array), 0, 0, 0, GLint(slot.layer), kSize,
                                 kSize, 1, GLsizei(bytes.size()), bytes.data());
  return bytes;
}

class GpuMemory : public ::testing::Test {
 protected:
  void SetUp() override {
    auto context = GlContext::createHeadless();
    ASSERT_TRUE(context.ok()) << context.error().message;
    mContext = std::move(context).value();
  }
  std::unique_ptr<GlContext> mContext;
};

TEST_F(GpuMemory, PagesDoubleAndNeverMoveWhatIsResident) {
  TextureArrays arrays;
  std::vector<TextureSlot> slots;
  for (uint32_t i = 0; i < 40; ++i) slots.push_back(arrays.upload(layerWithSeed(i)));
  // 8 + 16 + 32 layers: three pages, each layer still where it was put.
  EXPECT_EQ(arrays.pageCount(), 3u);
  EXPECT_EQ(arrays.allocatedBytes(), 56 * arrays.layerBytes(slots[0].array));
  EXPECT_NE(slots[0].array, slots[39].array);
  for (uint32_t i = 0; i < 40; ++i)
    EXPECT_EQ(readBack(arrays, slots[i]), layerWithSeed(i).mips[0]) << "layer " << i;
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
}

TEST_F(GpuMemory, EmptyPagesAreGivenBackAndOldPagesFillFirst) {
  TextureArrays arrays;
  std::vector<TextureSlot> slots;
  for (uint32_t i = 0; i < 40; ++i) slots.push_back(arrays.upload(layerWithSeed(i)));
  ASSERT_EQ(arrays.pageCount(), 3u);
  // Empty the newest page (layers 24..39, 32 places) while the others are full: it stays, or
  // the next upload would need a page again at once.
  for (uint32_t i = 24; i < 40; ++i) arrays.release(slots[i]);
  EXPECT_EQ(arrays.pageCount(), 3u);
  // With room elsewhere (half of it), an empty page goes.
  arrays.upload(layerWithSeed(50));  // lands in the newest page, layer 24
  for (uint32_t i = 4; i < 20; ++i) arrays.release(slots[i]);
  EXPECT_EQ(arrays.pageCount(), 3u);
  arrays.release(TextureSlot{slots[24].array, slots[24].layer, kSize, 0});
  EXPECT_EQ(arrays.pageCount(), 2u);
  EXPECT_EQ(arrays.allocatedBytes(), 24 * arrays.layerBytes(slots[0].array));
  // Freed layers of the oldest page are used before anything newer.
  const TextureSlot again = arrays.upload(layerWithSeed(99));
  EXPECT_EQ(again.array, slots[4].array);
  EXPECT_EQ(again.layer, slots[4].layer);
  EXPECT_EQ(readBack(arrays, again), layerWithSeed(99).mips[0]);
  EXPECT_EQ(readBack(arrays, slots[2]), layerWithSeed(2).mips[0]);
  EXPECT_EQ(readBack(arrays, slots[21]), layerWithSeed(21).mips[0]);
}

TEST_F(GpuMemory, AWorkerMakesPagesAheadOfNeed) {
  auto shared = mContext->createShared();
  ASSERT_TRUE(shared.ok()) << shared.error().message;
  auto worker = GlWorker::start(std::move(shared).value());
  ASSERT_TRUE(worker.ok()) << worker.error().message;
  TextureArrays arrays;
  arrays.setWorker(worker->get());
  std::vector<TextureSlot> slots;
  // The first page (8 layers) is made here; at half full the next is asked of the worker.
  for (uint32_t i = 0; i < 8; ++i) {
    ASSERT_TRUE(arrays.reserve(TextureEncoding::kBc5, kSize));
    slots.push_back(arrays.upload(layerWithSeed(i)));
  }
  EXPECT_EQ(arrays.pageCount(), 1u);
  // Full: no layer until the worker's page is adopted.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  while (!arrays.reserve(TextureEncoding::kBc5, kSize)) {
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the worker made no page";
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    arrays.poll();
  }
  EXPECT_EQ(arrays.pageCount(), 2u);
  // The worker's texture works in this context.
  slots.push_back(arrays.upload(layerWithSeed(8)));
  EXPECT_NE(slots[8].array, slots[0].array);
  EXPECT_EQ(readBack(arrays, slots[8]), layerWithSeed(8).mips[0]);
  EXPECT_EQ(readBack(arrays, slots[0]), layerWithSeed(0).mips[0]);
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  worker->reset();  // stops before the arrays go
}

TEST_F(GpuMemory, WorkerJobsRunInOrderWithTheirGlWorkDone) {
  auto shared = mContext->createShared();
  ASSERT_TRUE(shared.ok()) << shared.error().message;
  auto worker = GlWorker::start(std::move(shared).value());
  ASSERT_TRUE(worker.ok()) << worker.error().message;
  GLuint buffer = 0;
  std::vector<int> order;
  auto first = (*worker)->post([&] {
    glCreateBuffers(1, &buffer);
    const uint32_t value = 0xC0FFEEu;
    glNamedBufferStorage(buffer, sizeof value, &value, 0);
    order.push_back(1);
  });
  auto second = (*worker)->post([&] { order.push_back(2); });
  while (!second->done()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  EXPECT_TRUE(first->done());
  EXPECT_EQ(order, (std::vector<int>{1, 2}));
  uint32_t read = 0;
  glGetNamedBufferSubData(buffer, 0, sizeof read, &read);
  EXPECT_EQ(read, 0xC0FFEEu);
  glDeleteBuffers(1, &buffer);
}

// A chunk of `vertices` vertices whose values say which chunk it is.
ChunkGeometry geometryWithSeed(uint16_t seed, uint32_t vertices) {
  ChunkGeometry g;
  ChunkPart part;
  for (uint32_t i = 0; i < vertices; ++i)
    part.vertices.push_back({uint16_t(seed), uint16_t(i), uint16_t(i * 3), int16_t(seed)});
  for (uint32_t i = 0; i + 2 < vertices; i += 3)
    part.indices.insert(part.indices.end(), {i, i + 1, i + 2});
  part.surfaceIndexCount = uint32_t(part.indices.size());
  g.parts.push_back(std::move(part));
  return g;
}

TEST_F(GpuMemory, GeometryBuffersGrowAheadOnTheWorkerAndKeepWhatTheyHold) {
  auto shared = mContext->createShared();
  ASSERT_TRUE(shared.ok()) << shared.error().message;
  auto worker = GlWorker::start(std::move(shared).value());
  ASSERT_TRUE(worker.ok()) << worker.error().message;
  GpuChunkStore store(64 << 10);  // 4096 vertices and 16384 indices to begin with
  store.setWorker(worker->get());
  // The worker is held busy until the store has had to wait for it, so the first buffer
  // certainly fills before its successor is made (left to thread timing, a fast worker made
  // it in time once and the test proved nothing).
  struct Gate {
    std::promise<void> promise;
    bool open = false;
    void release() {
      if (!std::exchange(open, true)) promise.set_value();
    }
    ~Gate() { release(); }  // on every way out, or the worker's destructor would wait forever
  } gate;
  (*worker)->post([held = gate.promise.get_future().share()] { held.wait(); });
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(20);
  uint32_t uploaded = 0, deferred = 0;
  while (uploaded < 20) {  // 20 x 1000 vertices: the vertex buffer must grow twice
    ASSERT_LT(std::chrono::steady_clock::now(), deadline) << "the worker made no buffer";
    store.poll();
    const ChunkGeometry g = geometryWithSeed(uint16_t(uploaded), 1000);
    if (!store.reserve(g, nullptr)) {
      if (deferred++ == 0) {
        EXPECT_EQ(uploaded, 3u) << "4096 vertices hold three chunks and a quarter to spare";
        gate.release();
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    store.upload(uploaded, g);
    ++uploaded;
  }
  EXPECT_GT(deferred, 0u);
  // Every chunk's vertices are where the store says, after the buffers were replaced.
  for (uint32_t node = 0; node < 20; ++node) {
    const GpuChunkPart& p = store.find(node)->parts[0];
    std::vector<ChunkVertex> read(p.vertexCount);
    glGetNamedBufferSubData(store.vertexBuffer(), GLintptr(p.baseVertex * sizeof(ChunkVertex)),
                            GLsizeiptr(read.size() * sizeof(ChunkVertex)), read.data());
    EXPECT_EQ(read, geometryWithSeed(uint16_t(node), 1000).parts[0].vertices) << node;
  }
  EXPECT_EQ(glGetError(), GLenum(GL_NO_ERROR));
  gate.release();
  worker->reset();
}

}  // namespace
}  // namespace terralod
