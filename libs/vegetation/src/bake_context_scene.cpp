#include <embree3/rtcore.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <tuple>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>

#include "embree_shading.h"
#include "random_stream.h"
#include "terralod/vegetation/ldi_baker.h"
#include "terralod/vegetation/tile_placement.h"
#include "terralod/vegetation/wang_tiling.h"

namespace terralod::veg {
namespace {

// One surface a ray met: where, what colour, which way it faces (towards the viewer).
struct Hit {
  float depth;
  uint32_t instance, primitive, ray;
  glm::vec3 normal;
};

// The intersect context of a gathering ray: every hit is recorded and rejected, so that
// traversal goes on to the next one (docs: prior-art-vipm-ldi.md B.4, "Embree all-hits").
struct Gatherer {
  RTCIntersectContext context;
  std::vector<Hit>* hits;
  uint32_t ray;
  float depthOffset;
};

void gatherHit(const RTCFilterFunctionNArguments* args) {
  const Gatherer* g = reinterpret_cast<const Gatherer*>(args->context);
  args->valid[0] = 0;  // keep going
  RTCHitN* h = args->hit;
  Hit hit;
  hit.depth = g->depthOffset + RTCRayN_tfar(args->ray, args->N, 0);
  hit.instance = RTCHitN_instID(h, args->N, 0, 0);
  hit.primitive = RTCHitN_primID(h, args->N, 0);
  hit.ray = g->ray;
  hit.normal = {RTCHitN_Ng_x(h, args->N, 0), RTCHitN_Ng_y(h, args->N, 0),
                RTCHitN_Ng_z(h, args->N, 0)};
  g->hits->push_back(hit);
}

}  // namespace

struct ContextScene::Impl {
  struct Instance {
    const PlantMesh* mesh;
    glm::mat3 rotation;  // object to world, without scale (for normals)
    bool inCentre;
  };
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<RTCScene> meshScenes;
  std::vector<Instance> instances;  // by instance geometry id
  float tileSize = 0;
  uint64_t centreTriangles = 0;

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    for (RTCScene s : meshScenes) rtcReleaseScene(s);
    if (device) rtcReleaseDevice(device);
  }

  RTCScene meshScene(const PlantMesh& m) {
    RTCScene s = rtcNewScene(device);
    rtcSetSceneFlags(s, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), m.positions.size()));
    for (size_t i = 0; i < m.positions.size(); ++i)
      for (int k = 0; k < 3; ++k) v[3 * i + k] = m.positions[i][k];
    auto* t = static_cast<uint32_t*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(uint32_t), m.triangles.size()));
    for (size_t i = 0; i < m.triangles.size(); ++i)
      for (int k = 0; k < 3; ++k) t[3 * i + k] = m.triangles[i][k];
    rtcCommitGeometry(g);
    rtcAttachGeometry(s, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(s);
    meshScenes.push_back(s);
    return s;
  }
};

ContextScene::ContextScene(const std::vector<PrototileContent>& tiles,
                           const std::array<int, 9>& context, float tileSize,
                           const PlantLibrary& plants)
    : mImpl(std::make_unique<Impl>()) {
  Impl& m = *mImpl;
  m.tileSize = tileSize;
  m.device = rtcNewDevice(nullptr);
  if (!m.device) onEmbreeError(nullptr, rtcGetDeviceError(nullptr), "cannot create a device");
  rtcSetDeviceErrorFunction(m.device, onEmbreeError, nullptr);
  m.scene = rtcNewScene(m.device);
  rtcSetSceneFlags(m.scene, RTC_SCENE_FLAG_CONTEXT_FILTER_FUNCTION | RTC_SCENE_FLAG_ROBUST);
  std::vector<std::pair<const PlantMesh*, RTCScene>> made;
  auto sceneOf = [&](const PlantMesh& mesh) {
    for (auto& [p, s] : made)
      if (p == &mesh) return s;
    made.push_back({&mesh, m.meshScene(mesh)});
    return made.back().second;
  };
  for (int slot = 0; slot < 9; ++slot) {
    const float ox = float(slot % 3 - 1) * tileSize, oy = float(slot / 3 - 1) * tileSize;
    for (const PlacedObject& o : tiles[context[slot]].objects) {
      if (!centredIn(o, tileSize)) continue;  // drawn by the tile its centre is in
      const PlantMesh& mesh = plants.mesh(o.species, o.version);
      const float c = std::cos(o.rotation), s = std::sin(o.rotation);
      // Column-major 3×4: rotation about z times scale, then the translation.
      const float xfm[12] = {c * o.scale, s * o.scale, 0,       -s * o.scale, c * o.scale, 0,
                             0,           0,           o.scale, ox + o.x,     oy + o.y,    0};
      RTCGeometry inst = rtcNewGeometry(m.device, RTC_GEOMETRY_TYPE_INSTANCE);
      rtcSetGeometryInstancedScene(inst, sceneOf(mesh));
      rtcSetGeometryTransform(inst, 0, RTC_FORMAT_FLOAT3X4_COLUMN_MAJOR, xfm);
      rtcCommitGeometry(inst);
      const unsigned id = rtcAttachGeometry(m.scene, inst);
      rtcReleaseGeometry(inst);
      if (m.instances.size() <= id) m.instances.resize(id + 1);
      m.instances[id] = {&mesh, glm::mat3(c, s, 0, -s, c, 0, 0, 0, 1), slot == 4};
      if (slot == 4) m.centreTriangles += mesh.triangles.size();
    }
  }
  rtcCommitScene(m.scene);
}

ContextScene::~ContextScene() = default;

uint64_t ContextScene::trianglesInCentre() const {
  return mImpl->centreTriangles;
}

namespace {

// Sky visibility at a point: the share of cosine-weighted rays over the hemisphere of n that
// leave within `distance` without meeting a plant or the ground.
float skyVisibility(RTCScene scene, const glm::vec3& p, const glm::vec3& n, const Lighting& l,
                    RandomStream& rng) {
  if (l.occlusionRays == 0) return 1;
  const Hemisphere hemisphere(n);
  uint32_t open = 0;
  for (uint32_t k = 0; k < l.occlusionRays; ++k) {
    const double first = rng.uniform(), second = rng.uniform();
    const glm::vec3 d = hemisphere.direction(first, second);
    if (d.z < 0 && p.z / -d.z < l.occlusionDistance) continue;  // the ground
    RTCIntersectContext ctx;
    rtcInitIntersectContext(&ctx);
    RTCRay ray{};
    ray.org_x = p.x, ray.org_y = p.y, ray.org_z = p.z;
    ray.dir_x = d.x, ray.dir_y = d.y, ray.dir_z = d.z;
    ray.tnear = 1e-3f, ray.tfar = l.occlusionDistance, ray.mask = ~0u;
    rtcOccluded1(scene, &ctx, &ray);
    open += ray.tfar >= 0;
  }
  return float(open) / float(l.occlusionRays);
}

bool inSunlight(RTCScene scene, const glm::vec3& p, const Lighting& l) {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay ray{};
  ray.org_x = p.x, ray.org_y = p.y, ray.org_z = p.z;
  ray.dir_x = l.toSun.x, ray.dir_y = l.toSun.y, ray.dir_z = l.toSun.z;
  ray.tnear = 1e-3f, ray.tfar = 1e30f, ray.mask = ~0u;
  rtcOccluded1(scene, &ctx, &ray);
  return ray.tfar >= 0;
}

// One layer from a run of hits (nearest first): the mean depth, colour and normal of its hits,
// alpha the share of the pixel's rays among them, lit at the nearest hit.
DepthPixel shadeLayer(const ContextScene::Impl& m, const LdiCamera& cam, const Lighting& lighting,
                      const std::array<glm::vec3, 64>& origins, const Hit* hits, size_t n,
                      uint32_t rays, float depthScale, float depthStep, RandomStream& rng,
                      uint64_t& cast) {
  glm::vec3 albedo(0), normal(0);
  float depth = 0;
  uint64_t raysIn = 0;
  for (size_t i = 0; i < n; ++i) {
    const Hit& h = hits[i];
    const ContextScene::Impl::Instance& inst = m.instances[h.instance];
    const auto& c = inst.mesh->colors[h.primitive];
    albedo += glm::vec3(srgbToLinear(c[0]), srgbToLinear(c[1]), srgbToLinear(c[2]));
    glm::vec3 nw = glm::normalize(inst.rotation * h.normal);
    if (glm::dot(nw, cam.direction) > 0) nw = -nw;  // leaves are lit on the side one sees
    normal += nw;
    depth += h.depth;
    raysIn |= uint64_t(1) << h.ray;
  }
  albedo /= float(n);
  depth /= float(n);
  normal = glm::length(normal) > 1e-6f ? glm::normalize(normal) : -cam.direction;
  const glm::vec3 p =
      origins[hits[0].ray] + (hits[0].depth - cam.depthMin) * cam.direction + normal * 2e-3f;
  const float sky = skyVisibility(m.scene, p, normal, lighting, rng);
  const float facing = std::max(0.0f, glm::dot(normal, lighting.toSun));
  const float sun = facing > 0 && inSunlight(m.scene, p, lighting) ? facing : 0;
  cast += lighting.occlusionRays + (facing > 0);
  const glm::vec3 lit = albedo * (lighting.sky * sky + lighting.sun * sun + 0.04f);
  const uint32_t alpha = uint32_t(std::lround(255.0 * std::popcount(raysIn) / rays));
  const uint32_t rgba = linearToSrgb(lit.r) | uint32_t(linearToSrgb(lit.g)) << 8 |
                        uint32_t(linearToSrgb(lit.b)) << 16 | alpha << 24;
  const float q =
      std::clamp(std::round((depth - cam.depthMin) * depthScale / depthStep) * depthStep, 0.0f,
                 float(kLdiMaxDepth));
  return DepthPixel::make(rgba, uint32_t(std::lround(q)), encodeSplatNormal(normal));
}

}  // namespace

Ldi ContextScene::bake(const LdiCamera& cam, const SamplingSettings& sampling,
                       const Lighting& lighting, uint64_t& raysCast) const {
  const Impl& m = *mImpl;
  Ldi ldi;
  ldi.camera = cam;
  ldi.layerCounts.assign(size_t(cam.width) * cam.height, 0);
  const uint32_t side =
      std::max(1u, uint32_t(std::lround(std::sqrt(double(sampling.raysPerPixel)))));
  const uint32_t rays = std::min(64u, side * side);
  const float tolerance = sampling.layerTolerance * cam.pixelSize;
  const float depthScale = float(kLdiMaxDepth) / (cam.depthMax - cam.depthMin);
  const float depthStep =
      std::max(1.0f, std::floor(sampling.depthStep * cam.pixelSize * depthScale));
  // The jitter also varies with the camera, so that two cameras given one seed differ.
  RandomStream rng(sampling.seed ^ (uint64_t(cam.width) << 40) ^ (uint64_t(cam.height) << 20) ^
                   uint64_t(std::abs(cam.direction.x) * 1e6f));
  std::vector<Hit> hits;
  uint64_t cast = 0;
  for (uint32_t row = 0; row < cam.height; ++row)
    for (uint32_t col = 0; col < cam.width; ++col) {
      hits.clear();
      std::array<glm::vec3, 64> origins;
      for (uint32_t k = 0; k < rays; ++k) {  // one ray in each stratum of the pixel
        const float u =
            (float(col) + (float(k % side) + float(rng.uniform())) / float(side)) * cam.pixelSize;
        const float v =
            (float(row) + (float(k / side) + float(rng.uniform())) / float(side)) * cam.pixelSize;
        const glm::vec3 o =
            cam.origin + u * cam.axisU + v * cam.axisV + cam.depthMin * cam.direction;
        origins[k] = o;
        Gatherer g;
        rtcInitIntersectContext(&g.context);
        g.context.filter = gatherHit;
        g.hits = &hits;
        g.ray = k;
        g.depthOffset = cam.depthMin;
        RTCRayHit rh{};
        rh.ray.org_x = o.x, rh.ray.org_y = o.y, rh.ray.org_z = o.z;
        rh.ray.dir_x = cam.direction.x, rh.ray.dir_y = cam.direction.y,
        rh.ray.dir_z = cam.direction.z;
        rh.ray.tnear = 0, rh.ray.tfar = cam.depthMax - cam.depthMin, rh.ray.mask = ~0u;
        rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rtcIntersect1(m.scene, &g.context, &rh);
        ++cast;
      }
      // Surfaces in the centre tile (by the hit's footprint), each (ray, triangle) once,
      // nearest first; then runs of hits within the tolerance become one layer.
      std::erase_if(hits, [&](const Hit& h) {
        if (!sampling.centreTileOnly) return false;
        const glm::vec3 p = origins[h.ray] + (h.depth - cam.depthMin) * cam.direction;
        return p.x < 0 || p.x >= m.tileSize || p.y < 0 || p.y >= m.tileSize;
      });
      std::sort(hits.begin(), hits.end(), [](const Hit& a, const Hit& b) {
        return std::tie(a.ray, a.instance, a.primitive, a.depth) <
               std::tie(b.ray, b.instance, b.primitive, b.depth);
      });
      hits.erase(std::unique(hits.begin(), hits.end(),
                             [](const Hit& a, const Hit& b) {
                               return a.ray == b.ray && a.instance == b.instance &&
                                      a.primitive == b.primitive;
                             }),
                 hits.end());
      std::sort(hits.begin(), hits.end(),
                [](const Hit& a, const Hit& b) { return a.depth < b.depth; });
      uint8_t& count = ldi.layerCounts[size_t(row) * cam.width + col];
      for (size_t first = 0; first < hits.size() && count < 255;) {
        size_t end = first + 1;
        while (end < hits.size() && hits[end].depth - hits[first].depth <= tolerance) ++end;
        ldi.pixels.push_back(shadeLayer(m, cam, lighting, origins, &hits[first], end - first, rays,
                                        depthScale, depthStep, rng, cast));
        ++count;
        first = end;
      }
    }
  raysCast += cast;
  return ldi;
}

}  // namespace terralod::veg
