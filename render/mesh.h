// TriangleMesh: the renderer's input mesh, as the simulator produces it every frame.
//
// Fields:
//   name        used in error messages ("mesh 'jelly': ...")
//   positions   world-space vertex positions; all finite (Embree silently drops triangles with NaN/inf vertices,
//               so the renderer refuses them with an error instead)
//   normals     per-vertex shading normals, same count as positions, or empty for flat facets
//   uv          per-vertex texture coordinates, v up (OBJ convention), same count, or empty (all (0, 0))
//   triangles   vertex indices, counter-clockwise seen from outside
// Topology (uv, triangles, vertex count) is fixed once the mesh is added to a Scene; positions and normals change
// per frame through Scene::updateMesh.
#pragma once
#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace wobble::render {

struct TriangleMesh {
  std::string name;
  std::vector<Eigen::Vector3f> positions, normals;
  std::vector<Eigen::Vector2f> uv;
  std::vector<std::array<int, 3>> triangles;
};

// Throws std::invalid_argument naming the mesh, the vertex and its value if any value is NaN or infinite.
// what: "position" or "normal".
void checkFinite(std::string_view mesh_name, std::string_view what, std::span<const Eigen::Vector3f> values);

// Throws std::invalid_argument on mismatched array sizes, out-of-range indices or an empty mesh.
void checkMesh(const TriangleMesh& mesh);

}  // namespace wobble::render
