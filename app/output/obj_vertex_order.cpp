#include "app/output/obj_vertex_order.h"

#include <unordered_map>

namespace wobble {

ObjVertexOrder::ObjVertexOrder(const SurfaceMesh& mesh) {
  std::unordered_map<int, int> line_of_particle;
  line_of.reserve(mesh.vertexCount());
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    const auto [it, added] = line_of_particle.try_emplace(mesh.particle[v], int(first_vertex.size()));
    if (added) first_vertex.push_back(int(v));
    line_of.push_back(it->second);
  }
}

}  // namespace wobble
