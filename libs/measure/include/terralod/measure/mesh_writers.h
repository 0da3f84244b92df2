#pragma once
// Writes a LevelSurface as OBJ, PLY or glTF binary.

#include <optional>
#include <string>
#include <vector>

#include "terralod/core/atomic_file.h"
#include "terralod/measure/export_mesh.h"

namespace terralod {

enum class MeshFormat {
  kObj,  ///< Wavefront OBJ text: `v x y z`, `vt u v`, `vn x y z`, `f a/a/a b/b/b c/c/c`
         ///< (1-based), z up; with a texture `mtllib` and `usemtl` naming a .mtl beside it
  kPly,  ///< binary little-endian PLY: float x, y, z, nx, ny, nz, u, v; uchar-counted uint32
         ///< vertex_indices, z up; with a texture `comment TextureFile NAME.png`
  kGlb,  ///< glTF 2.0 binary: one mesh, one indexed primitive (POSITION, NORMAL, TEXCOORD_0),
         ///< one material, the texture embedded as PNG; y up as glTF requires
};

/// What goes with the mesh besides its geometry.
struct MeshExtras {
  std::string description;  ///< the file's comment, the glTF node's name
  /// The colour texture as PNG bytes: embedded in a .glb; for .obj and .ply written beside the
  /// mesh by the caller, under `textureFile`. Empty: no texture.
  std::vector<uint8_t> png;
  std::string textureFile;      ///< .obj, .ply: the PNG's file name, relative to the mesh
  std::string materialLibrary;  ///< .obj: the .mtl's file name, relative to the mesh
};

/// The format named by a path's extension (.obj, .ply, .glb, any case); nullopt otherwise.
std::optional<MeshFormat> meshFormatForPath(const std::string& path);

/// Writes `surface` into `file` (which the caller then commits). Fails when the file cannot be
/// written or the mesh does not fit the format (GLB's 4 GiB).
Status writeMesh(const LevelSurface& surface, MeshFormat format, const MeshExtras& extras,
                 AtomicFile& file);

/// The .mtl beside an OBJ: one material, "terrain", white and matte, its diffuse colour the
/// texture `textureFile`.
std::string objMaterialLibrary(const std::string& description, const std::string& textureFile);

}  // namespace terralod
