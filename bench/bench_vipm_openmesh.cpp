// VIPM chunk generation: OpenMesh's decimater (DecimaterT, half-edge collapses) against
// terralod's grid collapser (buildCollapseOrder, libs/vipm) on the same chunks as bench_vipm
// (vipm_chunks.h: 65 x 65 windows of tests/data DEMs, materials by height terciles), under the
// same constraints (collapse_order.h): corners locked, side vertices only along their side, no
// triangle turning over seen from above, and the paper's three material rules.
//
//   terralod   buildCollapseOrder(patch, MaterialRules::kOn)
//   om_vertical   DecimaterT + the constraints module + a priority module whose priority is
//                 the exact largest vertical distance of the samples under the new triangles
//                 (terralod::triangleError), so the order is comparable to terralod's
//   om_quadric    DecimaterT + ModQuadricT + ModNormalFlippingT + the constraints module
//                 (what docs/prior-art-vipm-ldi.md timed)
//
// Per chunk and method: the fastest of --repeat runs (the methods interleaved, so a busy
// machine slows all of them alike), the collapses done, and the triangles left when the
// order's monotone vertical error first exceeds 1 m (every order is replayed on terralod's
// PatchMesh, which also checks each OpenMesh collapse against terralod's rules).
//
//   build/release/bench/bench_vipm_openmesh [--chunks 16] [--repeat 3]
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModBaseT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "patch_mesh.h"
#include "terralod/vipm/collapse_order.h"
#include "terralod/vipm/progressive_mesh.h"
#include "vipm_chunks.h"

namespace {

using namespace terralod;

struct MeshTraits : OpenMesh::DefaultTraits {
  VertexAttributes(OpenMesh::Attributes::Status);
  EdgeAttributes(OpenMesh::Attributes::Status);
  FaceAttributes(OpenMesh::Attributes::Status);
};
using Mesh = OpenMesh::TriMesh_ArrayKernelT<MeshTraits>;

// One collapse as OpenMesh did it: v moved onto u, `removed` triangles died.
struct Step {
  uint16_t v, u;
  uint8_t removed;
};

// What a decimation run records (outside OpenMesh's own state).
struct Record {
  std::vector<Step> steps;
  size_t sideCrossings = 0;  // legal for OpenMesh but off the vertex's side: expected 0
};

enum Side { kWest = 1, kEast = 2, kSouth = 4, kNorth = 8 };

int sides(const GridPatch& p, uint32_t v) {
  const int32_t x = p.xOf(v), y = p.yOf(v);
  return (x == 0 ? kWest : 0) | (x == p.width - 1 ? kEast : 0) | (y == 0 ? kSouth : 0) |
         (y == p.height - 1 ? kNorth : 0);
}

// Twice the signed area, seen from above, of the triangle of patch points (a, b, c).
int64_t area2(const GridPatch& p, uint32_t a, uint32_t b, uint32_t c) {
  const int64_t ax = p.xOf(a), ay = p.yOf(a);
  return (p.xOf(b) - ax) * (p.yOf(c) - ay) - (p.xOf(c) - ax) * (p.yOf(b) - ay);
}

// A face's corners in its own (counter-clockwise) order.
std::array<uint16_t, 3> corners(const Mesh& m, Mesh::FaceHandle f) {
  const auto h0 = m.halfedge_handle(f), h1 = m.next_halfedge_handle(h0),
             h2 = m.next_halfedge_handle(h1);
  return {uint16_t(m.to_vertex_handle(h0).idx()), uint16_t(m.to_vertex_handle(h1).idx()),
          uint16_t(m.to_vertex_handle(h2).idx())};
}

// Calls fn(new triangle) for each triangle around v0 that survives v0 -> v1, with v0 replaced
// by v1; stops and returns false as soon as fn does.
template <class Fn>
bool forNewTriangles(const Mesh& m, Mesh::VertexHandle v0, Mesh::VertexHandle v1, Fn&& fn) {
  const auto v = uint16_t(v0.idx()), u = uint16_t(v1.idx());
  for (const auto f : m.vf_range(v0)) {
    std::array<uint16_t, 3> tri = corners(m, f);
    if (tri[0] == u || tri[1] == u || tri[2] == u) continue;
    for (uint16_t& w : tri)
      if (w == v) w = u;
    if (!fn(tri)) return false;
  }
  return true;
}

// terralod's constraints beyond OpenMesh's own topological tests (binary module): a side
// vertex only along its side, no triangle turning over seen from above, the material rules.
// It also records the collapses.
template <class MeshT>
class ModTerralodRulesT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModTerralodRulesT, MeshT, TerralodRules);
  explicit ModTerralodRulesT(MeshT& mesh) : Base(mesh, true) {}

  void setup(const GridPatch& patch, Record& record) {
    mPatch = &patch;
    mRecord = &record;
  }

  float collapse_priority(const CollapseInfo& ci) override {
    return legal(ci) ? float(Base::LEGAL_COLLAPSE) : float(Base::ILLEGAL_COLLAPSE);
  }

  void preprocess_collapse(const CollapseInfo& ci) override {
    mRecord->steps.push_back({uint16_t(ci.v0.idx()), uint16_t(ci.v1.idx()),
                              uint8_t(int(ci.fl.is_valid()) + int(ci.fr.is_valid()))});
  }

 private:
  bool legal(const CollapseInfo& ci) {
    const GridPatch& p = *mPatch;
    const Mesh& m = Base::mesh();
    const auto v = uint16_t(ci.v0.idx()), u = uint16_t(ci.v1.idx());
    const int sv = sides(p, v);
    if (sv != 0 && (sides(p, u) & sv) == 0) {
      ++mRecord->sideCrossings;
      return false;
    }
    const uint8_t mat = p.materials[v];
    if (p.materials[u] != mat) return false;  // rule 1
    const bool turns = !forNewTriangles(m, ci.v0, ci.v1, [&](const std::array<uint16_t, 3>& t) {
      return area2(p, t[0], t[1], t[2]) > 0;
    });
    if (turns) return false;
    if (onMaterialBoundary(ci.v0) && !onMaterialBoundary(ci.v1)) return false;  // rule 2
    // Rule 3: the triangle that covers v's position after the collapse has only corners of
    // v's material among those with a non-zero weight there.
    const int32_t px = p.xOf(v), py = p.yOf(v);
    bool covered = false;
    const bool kept = forNewTriangles(m, ci.v0, ci.v1, [&](const std::array<uint16_t, 3>& t) {
      int64_t w[3];
      for (int i = 0; i < 3; ++i) {
        const uint16_t b = t[(i + 1) % 3], c = t[(i + 2) % 3];
        w[i] = (p.xOf(b) - px) * int64_t(p.yOf(c) - py) - (p.xOf(c) - px) * int64_t(p.yOf(b) - py);
      }
      if (w[0] < 0 || w[1] < 0 || w[2] < 0) return true;
      covered = true;
      for (int i = 0; i < 3; ++i)
        if (w[i] > 0 && p.materials[t[i]] != mat) return false;
      return true;
    });
    return kept && covered;
  }

  bool onMaterialBoundary(Mesh::VertexHandle v) {
    const Mesh& m = Base::mesh();
    const uint8_t mat = mPatch->materials[v.idx()];
    for (const auto w : m.vv_range(v))
      if (mPatch->materials[w.idx()] != mat) return true;
    return false;
  }

  const GridPatch* mPatch = nullptr;
  Record* mRecord = nullptr;
};

// Priority: the largest vertical distance between the samples under the collapse's new
// triangles and those triangles (terralod's collapse error, without its cache).
template <class MeshT>
class ModVerticalT : public OpenMesh::Decimater::ModBaseT<MeshT> {
 public:
  DECIMATING_MODULE(ModVerticalT, MeshT, VerticalError);
  explicit ModVerticalT(MeshT& mesh) : Base(mesh, false) {}
  void setup(const GridPatch& patch) { mPatch = &patch; }

  float collapse_priority(const CollapseInfo& ci) override {
    double worst = 0.0;
    const bool ok = forNewTriangles(Base::mesh(), ci.v0, ci.v1, [&](const auto& t) {
      if (area2(*mPatch, t[0], t[1], t[2]) <= 0) return false;
      worst = std::max(worst, triangleError(*mPatch, t[0], t[1], t[2]));
      return true;
    });
    return ok ? float(worst) : float(Base::ILLEGAL_COLLAPSE);
  }

 private:
  const GridPatch* mPatch = nullptr;
};

enum class Method { kTerralod, kVertical, kQuadric };
constexpr Method kMethods[] = {Method::kTerralod, Method::kVertical, Method::kQuadric};
const char* name(Method m) {
  return m == Method::kTerralod   ? "terralod"
         : m == Method::kVertical ? "om_vertical"
                                  : "om_quadric";
}

// The grid triangulation as an OpenMesh mesh (metres), corners locked.
void buildMesh(const GridPatch& p, std::array<double, 2> spacing, Mesh& mesh) {
  for (uint32_t id = 0; id < p.pointCount(); ++id)
    mesh.add_vertex(Mesh::Point(float(p.xOf(id) * spacing[0]), float(p.yOf(id) * spacing[1]),
                                p.vertexHeight(id)));
  for (const auto& t : gridTriangulation(p.width, p.height))
    mesh.add_face(mesh.vertex_handle(t[0]), mesh.vertex_handle(t[1]), mesh.vertex_handle(t[2]));
  for (const uint16_t c :
       {p.id(0, 0), p.id(p.width - 1, 0), p.id(0, p.height - 1), p.id(p.width - 1, p.height - 1)})
    mesh.status(mesh.vertex_handle(c)).set_locked(true);
}

void decimate(const GridPatch& p, std::array<double, 2> spacing, Method method, Record& record) {
  namespace D = OpenMesh::Decimater;
  Mesh mesh;
  buildMesh(p, spacing, mesh);
  D::DecimaterT<Mesh> decimater(mesh);
  typename ModTerralodRulesT<Mesh>::Handle rules;
  decimater.add(rules);
  decimater.module(rules).setup(p, record);
  typename ModVerticalT<Mesh>::Handle vertical;
  typename D::ModQuadricT<Mesh>::Handle quadric;
  typename D::ModNormalFlippingT<Mesh>::Handle flipping;
  if (method == Method::kVertical) {
    decimater.add(vertical);
    decimater.module(vertical).setup(p);
  } else {
    mesh.request_face_normals();  // ModNormalFlippingT's; it would compute them and say so
    mesh.update_face_normals();
    decimater.add(quadric);
    decimater.module(quadric).unset_max_err();
    decimater.add(flipping);
  }
  if (!decimater.initialize()) {
    std::fprintf(stderr, "bench_vipm_openmesh: OpenMesh's decimater did not initialise\n");
    std::exit(1);
  }
  decimater.decimate();  // to exhaustion
}

struct Quality {
  size_t trianglesAt1m = 0;  // before the first collapse whose running error exceeds 1 m
  size_t illegal = 0;        // collapses terralod's rules refuse
  size_t mismatches = 0;     // dying-triangle counts that disagree with the replay
  bool broken = false;       // a collapse terralod's mesh cannot do at all
};

// Replays `steps` on terralod's PatchMesh: the true error of each collapse (its new triangles'
// largest vertical distance to the samples), its legality under terralod's rules, and the
// triangles left at 1 m.
Quality replay(const GridPatch& p, const std::vector<Step>& steps) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  PatchMesh ruled(p, MaterialRules::kOn), plain(p, MaterialRules::kOff);
  Quality q;
  size_t triangles = size_t(2) * size_t(p.width - 1) * size_t(p.height - 1);
  double running = 0.0;
  bool over = false;
  for (const Step& s : steps) {
    double e = ruled.collapseError(s.v, s.u, kInf);
    if (!std::isfinite(e)) {
      ++q.illegal;
      e = plain.collapseError(s.v, s.u, kInf);
      if (!std::isfinite(e)) {
        q.broken = true;
        break;
      }
    }
    ruled.collapse(s.v, s.u);
    plain.collapse(s.v, s.u);
    const size_t removed = (sides(p, s.v) & sides(p, s.u)) != 0 ? 1 : 2;
    if (s.removed != 0 && s.removed != removed) ++q.mismatches;
    running = std::max(running, e);
    if (!over && running > 1.0) {
      over = true;
      q.trianglesAt1m = triangles;
    }
    triangles -= removed;
  }
  if (!over) q.trianglesAt1m = triangles;
  return q;
}

struct Outcome {
  double ms = std::numeric_limits<double>::infinity();
  size_t collapses = 0;
  Quality quality;
  size_t sideCrossings = 0;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n == 0 ? 0.0 : n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  int chunkCount = 16, repeat = 3;
  for (int i = 1; i < argc; ++i) {
    if (i + 1 < argc && std::strcmp(argv[i], "--chunks") == 0) {
      chunkCount = std::atoi(argv[++i]);
    } else if (i + 1 < argc && std::strcmp(argv[i], "--repeat") == 0) {
      repeat = std::atoi(argv[++i]);
    } else {
      std::fprintf(stderr, "usage: bench_vipm_openmesh [--chunks N] [--repeat R]\n");
      return 2;
    }
  }
  if (chunkCount < 1 || repeat < 1) {
    std::fprintf(stderr, "bench_vipm_openmesh: --chunks and --repeat must be at least 1\n");
    return 2;
  }
  const char* files[] = {"crater_lake_0513.bt", "zion_srtm3_utm12_30m.tif"};
  // results[file][method][chunk]
  std::vector<std::array<std::vector<Outcome>, 3>> results;
  for (const char* file : files) {
    std::array<double, 2> spacing{};
    const auto patches = bench::chunks(file, chunkCount, &spacing);
    if (patches.empty()) {
      std::fprintf(stderr, "bench_vipm_openmesh: cannot read %s/%s\n", TERRALOD_TEST_DATA_DIR,
                   file);
      return 1;
    }
    auto& perMethod = results.emplace_back();
    for (auto& r : perMethod) r.resize(patches.size());
    for (size_t k = 0; k < patches.size(); ++k) {
      const GridPatch& p = patches[k];
      for (int rep = 0; rep < repeat; ++rep) {
        for (const Method m : kMethods) {
          Outcome& r = perMethod[size_t(m)][k];
          const auto t0 = std::chrono::steady_clock::now();
          std::vector<Step> steps;
          size_t crossings = 0;
          if (m == Method::kTerralod) {
            const CollapseOrder order = buildCollapseOrder(p, MaterialRules::kOn);
            r.ms = std::min(r.ms, std::chrono::duration<double, std::milli>(
                                      std::chrono::steady_clock::now() - t0)
                                      .count());
            for (const Collapse& c : order.collapses) steps.push_back({c.vertex, c.target, 0});
            if (rep == 0) {
              // Cross-check the replay against the lead's own progressive mesh at 1 m.
              const size_t pm = makeProgressiveMesh(p, order, 1.0).triangles.size();
              const size_t replayed = replay(p, steps).trianglesAt1m;
              if (pm != replayed)
                std::fprintf(stderr, "%s chunk %zu: makeProgressiveMesh %zu, replay %zu\n", file, k,
                             pm, replayed);
            }
          } else {
            Record record;
            decimate(p, spacing, m, record);
            r.ms = std::min(r.ms, std::chrono::duration<double, std::milli>(
                                      std::chrono::steady_clock::now() - t0)
                                      .count());
            steps = std::move(record.steps);
            crossings = record.sideCrossings;
          }
          if (rep == 0) {
            r.collapses = steps.size();
            r.quality = replay(p, steps);
            r.sideCrossings = crossings;
          }
        }
      }
    }
  }

  std::printf("%-26s %-12s %9s %9s %10s %11s %10s %8s\n", "chunks", "method", "ms_median", "ms_max",
              "x_terralod", "collapses", "tris_at_1m", "illegal");
  for (size_t f = 0; f <= results.size(); ++f) {  // each file, then both together
    for (const Method m : kMethods) {
      std::vector<double> ms, ratio, collapses, tris;
      size_t illegal = 0, crossings = 0, mismatches = 0, broken = 0;
      for (size_t g = 0; g < results.size(); ++g) {
        if (f < results.size() && g != f) continue;
        const auto& mine = results[g][size_t(m)];
        const auto& base = results[g][size_t(Method::kTerralod)];
        for (size_t k = 0; k < mine.size(); ++k) {
          ms.push_back(mine[k].ms);
          ratio.push_back(mine[k].ms / base[k].ms);
          collapses.push_back(double(mine[k].collapses));
          tris.push_back(double(mine[k].quality.trianglesAt1m));
          illegal += mine[k].quality.illegal;
          mismatches += mine[k].quality.mismatches;
          broken += mine[k].quality.broken;
          crossings += mine[k].sideCrossings;
        }
      }
      const std::string label = f < results.size()
                                    ? files[f] + std::string(" x") + std::to_string(ms.size())
                                    : "both x" + std::to_string(ms.size());
      std::printf("%-26s %-12s %9.1f %9.1f %10.2f %11.0f %10.0f %8zu\n", label.c_str(), name(m),
                  median(ms), *std::max_element(ms.begin(), ms.end()), median(ratio),
                  median(collapses), median(tris), illegal);
      if (crossings + mismatches + broken != 0)
        std::printf(
            "  %s: %zu side crossings refused, %zu triangle-count mismatches, %zu chunks "
            "with a collapse terralod's mesh cannot do\n",
            name(m), crossings, mismatches, broken);
    }
  }
  std::printf(
      "ms: fastest of %d runs per chunk; x_terralod: median over chunks of ms / terralod's ms on "
      "the same chunk; collapses, tris_at_1m: medians; illegal: collapses (all chunks) that "
      "terralod's rules refuse\n",
      repeat);
  return 0;
}
