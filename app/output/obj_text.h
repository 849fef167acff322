// The text of the OBJ and MTL files wobble writes for a body (obj_sequence.h), made here rather than by assimp's
// exporter so that the `v` order is ObjVertexOrder's (assimp renumbers vertices by first use and merges equal
// positions). The OBJ: `v` lines in ObjVertexOrder, one `vt` and one `vn` per surface vertex, the body's triangles in
// order as `f v/vt/vn`, one object and one material named after the body. Numbers are the shortest text that reads
// back as the same float, so the OBJ and the PC2 of one frame hold equal values.
// The MTL: that material with the scene's colour (`Kd`, linear RGB, multiplying the texture) and the texture file
// (`map_Kd`, a name beside the MTL); a glossy jelly gets a white specular lobe (`Ks`, `Ns`), a diffuse body none.
#pragma once
#include <cstdint>
#include <string>

#include "app/output/obj_vertex_order.h"
#include "sim/surface.h"
#include "sim/types.h"

namespace wobble {

std::string objText(const std::string& name, const SurfaceMesh& mesh, const ObjVertexOrder& order,
                    const SurfaceFrame& frame, const std::string& mtl_file);

// The most bytes objText can give for this mesh, whatever its positions and normals: the lines that depend on the
// topology alone (names, `vt`, `f`) exactly, and every `v` and `vn` number at its longest (15 characters,
// "-1.17549435e-38"). A frame's numbers usually print in 8 to 12, so the bound is about 1.5 times the file.
std::uint64_t objTextSizeBound(const std::string& name, const SurfaceMesh& mesh, const ObjVertexOrder& order,
                               const std::string& mtl_file);

struct ObjMaterial {
  std::string name;
  Vec3 color{1, 1, 1};
  std::string texture;  // file name beside the MTL, or empty
  bool glossy = false;
};

std::string mtlText(const ObjMaterial& material);

}  // namespace wobble
