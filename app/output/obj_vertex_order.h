// ObjVertexOrder: which point of a body's surface each `v` line of its OBJ files stands for, and so each point of
// its PC2 point cache (pc2_writer.h). One order, shared by both writers, because a point cache plays on a mesh only
// when its points are the mesh's vertices in the mesh's order.
// The invariant: one `v` per surface particle, in the order of each particle's first surface vertex; the jelly's
// seam vertices (one particle, several UVs and normals) share their particle's `v`. It depends on the topology
// alone, so every frame, the base OBJ and the PC2 of a body agree, whatever the positions (two particles at one
// place keep two `v` lines).
#pragma once
#include <vector>

#include "sim/surface.h"

namespace wobble {

struct ObjVertexOrder {
  explicit ObjVertexOrder(const SurfaceMesh& mesh);

  std::vector<int> first_vertex;  // v line i (0-based) -> the first surface vertex of its particle
  std::vector<int> line_of;       // surface vertex -> its particle's v line (0-based)

  std::size_t size() const { return first_vertex.size(); }
};

}  // namespace wobble
