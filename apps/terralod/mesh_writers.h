#pragma once
// Writes a LevelSurface as OBJ, PLY or glTF binary.

#include <optional>
#include <string>

#include "export_mesh.h"
#include "terralod/core/atomic_file.h"

namespace terralod::cli {

enum class MeshFormat {
  kObj,  ///< Wavefront OBJ text: `v x y z`, `f a b c` (1-based), z up
  kPly,  ///< binary little-endian PLY: float x, y, z; uchar-counted uint32 vertex_indices, z up
  kGlb,  ///< glTF 2.0 binary: one mesh, one indexed primitive, y up as glTF requires
};

/// The format named by a path's extension (.obj, .ply, .glb, any case); nullopt otherwise.
std::optional<MeshFormat> meshFormatForPath(const std::string& path);

/// Writes `surface` into `file` (which the caller then commits); `description` goes into the
/// file's comment or the glTF node's name. Fails when the file cannot be written or the mesh
/// does not fit the format (GLB's 4 GiB).
Status writeMesh(const LevelSurface& surface, MeshFormat format, const std::string& description,
                 AtomicFile& file);

}  // namespace terralod::cli
