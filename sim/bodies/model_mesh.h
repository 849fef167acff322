// A user's triangle model as the simulator takes it (read from a file by app/scene/model_file.h): points in the file's
// order, triangles over them, and optional texture coordinates per triangle corner. Shared by the mesh jelly
// (bodies/mesh_jelly.h) and the mesh collider (colliders/mesh.h): checks, placement, and the geometric queries both
// use.
#pragma once
#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "sim/types.h"

namespace wobble {

struct ModelMesh {
  std::vector<Vec3> points;                               // in the file's vertex order
  std::vector<std::array<int, 3>> triangles;              // counter-clockwise seen from outside
  std::vector<std::array<Eigen::Vector2f, 3>> corner_uv;  // per triangle corner; empty when the file has none
};

// Placement: the model's bounding-box centre goes to `center`, scaled by `scale`, rotated about that centre.
struct Placement {
  Vec3 center = Vec3::Zero();
  double scale = 1;
  Vec3 rotation_axis = Vec3::UnitY();
  double rotation_deg = 0;

  Eigen::Matrix3d rotation() const;
};

// The first thing wrong with the mesh for a body or collider, as a sentence ("" when fine): empty, a non-finite
// coordinate (naming the vertex), a triangle index out of range, a degenerate model (zero area, or zero volume when
// closed is required), an edge shared by more than two triangles (non-manifold, naming its vertices) and, when
// `closed`, boundary edges (how many, and one of them with its position).
std::string checkModel(const ModelMesh& mesh, bool closed);

// The points moved into the model's local frame: bounding-box centre at the origin, times scale (no rotation).
std::vector<Vec3> localPoints(const ModelMesh& mesh, double scale);

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// The enclosed volume of a closed mesh (divergence theorem: sum of signed tetrahedra from the origin).
double meshVolume(const std::vector<Vec3>& points, const std::vector<std::array<int, 3>>& triangles);

}  // namespace wobble
