#include "terralod/vegetation/field_tracer.h"

#include <embree3/rtcore.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/mat3x3.hpp>

#include "embree_shading.h"
#include "random_stream.h"
#include "terralod/core/parallel.h"
#include "terralod/vegetation/ldi_warp.h"
#include "terralod/vegetation/tile_placement.h"

namespace terralod::veg {

struct FieldTracer::Impl {
  struct Prototile {
    RTCScene scene = nullptr;
    std::vector<std::array<uint8_t, 3>> colors;  // by triangle
  };
  struct Instance {  // one half of a tile
    int prototile = 0;
    TileHalf half = TileHalf::kSouthEast;
    glm::mat4 toWorld{1.0f}, toTile{1.0f};
    glm::mat3 normalToWorld{1.0f};
  };
  RTCDevice device = nullptr;
  std::array<Prototile, kPrototiles> prototiles;
  RTCScene field = nullptr;
  std::vector<Instance> instances;  // by geometry id in `field`
  glm::dvec3 origin{0.0};           // world position of the field scene's origin
  uint64_t triangles = 0;

  ~Impl() {
    if (field) rtcReleaseScene(field);
    for (Prototile& p : prototiles)
      if (p.scene) rtcReleaseScene(p.scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

// Keeps a hit only over the half of its tile the instance stands for (a point takes the
// shear of the half it lies over, as in the warp); the ray is in the tile's frame there.
struct HalfContext {
  RTCIntersectContext context;
  const FieldTracer::Impl* impl;
};

void keepOwnHalf(const RTCFilterFunctionNArguments* args) {
  const HalfContext* c = reinterpret_cast<const HalfContext*>(args->context);
  const unsigned id = RTCHitN_instID(args->hit, args->N, 0, 0);
  if (id == RTC_INVALID_GEOMETRY_ID || id >= c->impl->instances.size()) return;
  const float t = RTCRayN_tfar(args->ray, args->N, 0);
  const float x = RTCRayN_org_x(args->ray, args->N, 0) + t * RTCRayN_dir_x(args->ray, args->N, 0);
  const float y = RTCRayN_org_y(args->ray, args->N, 0) + t * RTCRayN_dir_y(args->ray, args->N, 0);
  if (halfOf(x, y) != c->impl->instances[id].half) args->valid[0] = 0;
}

// The field's scene with the half filter: whether anything lies within `far` along the ray.
bool occluded(const FieldTracer::Impl& m, const glm::vec3& origin, const glm::vec3& direction,
              float far) {
  HalfContext c;
  rtcInitIntersectContext(&c.context);
  c.context.filter = keepOwnHalf;
  c.impl = &m;
  RTCRay ray{};
  ray.org_x = origin.x, ray.org_y = origin.y, ray.org_z = origin.z;
  ray.dir_x = direction.x, ray.dir_y = direction.y, ray.dir_z = direction.z;
  ray.tnear = 1e-3f, ray.tfar = far, ray.mask = ~0u;
  rtcOccluded1(m.field, &c.context, &ray);
  return ray.tfar < 0;
}

struct Shaded {
  glm::vec3 linear{0};
  float viewDepth = 0;
};

// Lights a hit as the baker lights a layer: sky light scaled by the share of occlusion rays
// that leave (the ground below the tile's plane blocks too), sun with a shadow ray.
Shaded shade(const FieldTracer::Impl& m, const RTCRayHit& rh, const glm::vec3& direction,
             const Lighting& l, RandomStream& rng, uint64_t& rays) {
  const FieldTracer::Impl::Instance& inst = m.instances[rh.hit.instID[0]];
  const auto& c = m.prototiles[size_t(inst.prototile)].colors[rh.hit.primID];
  const glm::vec3 albedo(srgbToLinear(c[0]), srgbToLinear(c[1]), srgbToLinear(c[2]));
  glm::vec3 n =
      glm::normalize(inst.normalToWorld * glm::vec3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z));
  if (glm::dot(n, direction) > 0) n = -n;  // leaves are lit on the side one sees
  const glm::vec3 origin(rh.ray.org_x, rh.ray.org_y, rh.ray.org_z);
  const glm::vec3 p = origin + rh.ray.tfar * direction + n * 2e-3f;
  const float aboveGround = (inst.toTile * glm::vec4(p, 1.0f)).z;
  float sky = 1;
  if (l.occlusionRays > 0) {
    const Hemisphere hemisphere(n);
    uint32_t open = 0;
    for (uint32_t k = 0; k < l.occlusionRays; ++k) {
      const double first = rng.uniform(), second = rng.uniform();
      const glm::vec3 d = hemisphere.direction(first, second);
      if (d.z < 0 && aboveGround / -d.z < l.occlusionDistance) continue;  // the ground
      open += !occluded(m, p, d, l.occlusionDistance);
    }
    rays += l.occlusionRays;
    sky = float(open) / float(l.occlusionRays);
  }
  const float facing = std::max(0.0f, glm::dot(n, l.toSun));
  float sun = 0;
  if (facing > 0) {
    ++rays;
    if (!occluded(m, p, l.toSun, 1e30f)) sun = facing;
  }
  return {albedo * (l.sky * sky + l.sun * sun + 0.04f), 0};
}

}  // namespace

FieldTracer::FieldTracer(const VegetationHeader& header, const PlantLibrary& plants)
    : mImpl(std::make_unique<Impl>()) {
  Impl& m = *mImpl;
  m.device = rtcNewDevice(nullptr);
  if (!m.device) onEmbreeError(nullptr, rtcGetDeviceError(nullptr), "cannot create a device");
  rtcSetDeviceErrorFunction(m.device, onEmbreeError, nullptr);
  const float size = header.settings.tileSize;
  for (int k = 0; k < kPrototiles; ++k) {
    // The plants centred in the prototile, as one mesh in its frame.
    std::vector<glm::vec3> positions;
    std::vector<std::array<uint32_t, 3>> triangles;
    Impl::Prototile& proto = m.prototiles[size_t(k)];
    for (const PlacedObject& o : header.tiles[size_t(k)].objects) {
      if (!centredIn(o, size)) continue;
      const PlantMesh& mesh = plants.mesh(o.species, o.version);
      const float c = std::cos(o.rotation), s = std::sin(o.rotation);
      const uint32_t first = uint32_t(positions.size());
      for (const glm::vec3& v : mesh.positions)
        positions.push_back({o.x + o.scale * (c * v.x - s * v.y),
                             o.y + o.scale * (s * v.x + c * v.y), o.scale * v.z});
      for (const auto& t : mesh.triangles)
        triangles.push_back({first + t[0], first + t[1], first + t[2]});
      proto.colors.insert(proto.colors.end(), mesh.colors.begin(), mesh.colors.end());
    }
    m.triangles += triangles.size();
    proto.scene = rtcNewScene(m.device);
    rtcSetSceneFlags(proto.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
    if (!triangles.empty()) {
      RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_TRIANGLE);
      auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), positions.size()));
      for (size_t i = 0; i < positions.size(); ++i)
        for (int a = 0; a < 3; ++a) v[3 * i + size_t(a)] = positions[i][a];
      auto* t = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), triangles.size()));
      for (size_t i = 0; i < triangles.size(); ++i)
        for (int a = 0; a < 3; ++a) t[3 * i + size_t(a)] = triangles[i][size_t(a)];
      rtcCommitGeometry(g);
      rtcAttachGeometry(proto.scene, g);
      rtcReleaseGeometry(g);
    }
    rtcCommitScene(proto.scene);
  }
}

FieldTracer::~FieldTracer() = default;

uint64_t FieldTracer::triangles() const {
  return mImpl->triangles;
}

void FieldTracer::setTiles(std::span<const TracedTile> tiles) {
  Impl& m = *mImpl;
  if (m.field) rtcReleaseScene(m.field);
  m.field = rtcNewScene(m.device);
  rtcSetSceneFlags(m.field, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
  m.instances.clear();
  // The scene's origin at the first tile, so float keeps millimetres kilometres away.
  m.origin = tiles.empty() ? glm::dvec3(0.0)
                           : glm::dvec3(tiles[0].placement.origin.x, tiles[0].placement.origin.y,
                                        tiles[0].placement.heights[0]);
  for (const TracedTile& t : tiles) {
    TileOnTerrain local = t.placement;
    local.origin -= glm::vec2(m.origin);
    for (float& h : local.heights) h -= float(m.origin.z);
    for (TileHalf half : {TileHalf::kSouthEast, TileHalf::kNorthWest}) {
      Impl::Instance inst;
      inst.prototile = t.prototile;
      inst.half = half;
      inst.toWorld = halfShear(local, half);
      inst.toTile = glm::inverse(inst.toWorld);
      inst.normalToWorld = glm::transpose(glm::mat3(inst.toTile));
      RTCGeometry g = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(g, m.prototiles[size_t(t.prototile)].scene);
      rtcSetGeometryTransform(g, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &inst.toWorld[0][0]);
      rtcCommitGeometry(g);
      const unsigned id = rtcAttachGeometry(m.field, g);
      rtcReleaseGeometry(g);
      if (m.instances.size() <= id) m.instances.resize(id + 1);
      m.instances[id] = inst;
    }
  }
  rtcCommitScene(m.field);
}

TraceStats FieldTracer::trace(const View& view, std::span<const float> terrainViewDepth,
                              const PictureSpans& out, const TraceOptions& options) const {
  const Impl& m = *mImpl;
  const auto start = std::chrono::steady_clock::now();
  TraceStats stats;
  stats.top = 0;
  stats.bottom = out.height;
  const uint32_t side =
      std::max(1u, uint32_t(std::lround(std::sqrt(double(options.raysPerPixel)))));
  const uint32_t rays = side * side;
  const glm::vec3 eye(view.camera.eye - m.origin);
  std::vector<uint64_t> cast(std::max(1u, options.threads), 0);
  parallelFor(size_t(out.height), std::max(1u, options.threads), [&](size_t row, unsigned worker) {
    RandomStream rng(0x5eedull * (row + 1));
    for (int col = 0; col < out.width; ++col) {
      const size_t i = row * size_t(out.width) + size_t(col);
      const float terrain = terrainViewDepth[i];
      glm::vec3 sum(0);
      uint32_t hits = 0;
      float nearest = std::numeric_limits<float>::infinity();
      for (uint32_t k = 0; k < rays; ++k) {
        // A ray through a jittered point of the pixel's stratum k.
        const double sx =
            (double(col) + (double(k % side) + rng.uniform()) / side) / double(out.width) * 2.0 -
            1.0;
        const double sy = 1.0 - (double(row) + (double(k / side) + rng.uniform()) / side) /
                                    double(out.height) * 2.0;
        const glm::dvec3 dir = view.forward + sx * view.tanHalfWidth * view.right +
                               sy * view.tanHalfHeight * view.up;  // unit along forward
        const glm::vec3 direction(glm::normalize(dir));
        const float metresPerViewDepth = float(glm::length(dir));
        HalfContext c;
        rtcInitIntersectContext(&c.context);
        c.context.filter = keepOwnHalf;
        c.impl = &m;
        RTCRayHit rh{};
        rh.ray.org_x = eye.x, rh.ray.org_y = eye.y, rh.ray.org_z = eye.z;
        rh.ray.dir_x = direction.x, rh.ray.dir_y = direction.y, rh.ray.dir_z = direction.z;
        rh.ray.tnear = 0;
        rh.ray.tfar = std::isfinite(terrain) ? terrain * metresPerViewDepth : 1e30f;
        rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(m.field, &c.context, &rh);
        ++cast[worker];
        if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
        ++hits;
        sum += shade(m, rh, direction, options.lighting, rng, cast[worker]).linear;
        nearest = std::min(nearest, rh.ray.tfar / metresPerViewDepth);
      }
      if (hits == 0) {
        out.rgba[i] = 0;
        out.viewDepth[i] = std::numeric_limits<float>::infinity();
        continue;
      }
      const glm::vec3 lit = sum / float(hits);
      const float alpha = float(hits) / float(rays);
      // Premultiplied, display-encoded like the LDIs' colours.
      const float rgba[4] = {float(linearToSrgb(lit.r)) / 255.0f * alpha,
                             float(linearToSrgb(lit.g)) / 255.0f * alpha,
                             float(linearToSrgb(lit.b)) / 255.0f * alpha, alpha};
      out.rgba[i] = packRgba8(rgba);
      out.viewDepth[i] = nearest;
    }
  });
  for (uint64_t c : cast) stats.rays += c;
  stats.ms =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

}  // namespace terralod::veg
