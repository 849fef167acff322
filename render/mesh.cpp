// Validation of renderer input meshes (see mesh.h).
#include "render/mesh.h"

#include <sstream>
#include <stdexcept>

namespace wobble::render {

void checkFinite(std::string_view mesh_name, std::string_view what, std::span<const Eigen::Vector3f> values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i].allFinite()) continue;
    std::ostringstream msg;
    msg << "mesh '" << mesh_name << "': vertex " << i << " " << what << " is not finite (" << values[i].x() << ", "
        << values[i].y() << ", " << values[i].z() << "); the simulation probably blew up before this frame";
    throw std::invalid_argument(msg.str());
  }
}

void checkMesh(const TriangleMesh& m) {
  const auto fail = [&](const std::string& what) { throw std::invalid_argument("mesh '" + m.name + "': " + what); };
  const std::size_t n = m.positions.size();
  if (n == 0 || m.triangles.empty()) fail("has no vertices or no triangles");
  if (!m.normals.empty() && m.normals.size() != n)
    fail(std::to_string(m.normals.size()) + " normals for " + std::to_string(n) + " vertices");
  if (!m.uv.empty() && m.uv.size() != n)
    fail(std::to_string(m.uv.size()) + " uvs for " + std::to_string(n) + " vertices");
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int k : m.triangles[t])
      if (k < 0 || std::size_t(k) >= n)
        fail("triangle " + std::to_string(t) + " uses vertex " + std::to_string(k) + ", but there are " +
             std::to_string(n) + " vertices");
  for (std::size_t i = 0; i < m.uv.size(); ++i)
    if (!m.uv[i].allFinite()) fail("vertex " + std::to_string(i) + " uv is not finite");
  checkFinite(m.name, "position", m.positions);
  checkFinite(m.name, "normal", m.normals);
}

}  // namespace wobble::render
