// Mesh jelly: a jelly of any closed triangle model. The model's inside is filled with a cube lattice (cells inside
// the model or cut by its surface), joined by the cube jelly's structural, shear and bending springs, and the model's
// surface is embedded in it: each model vertex is the trilinear blend of the 8 particles of its lattice cell (free-form
// deformation: T. W. Sederberg and S. R. Parry, "Free-form deformation of solid geometric models", SIGGRAPH 1986).
//
// Parameters:
//   model           the closed triangle mesh (checkModel(model, true) == "")
//   cells = 10      lattice cells along the model's longest bounding-box side (the other sides get as many cells of
//                   the same size as they need to cover the model)
//   placement       the model's bounding-box centre goes to `center`, times `scale`, rotated about that centre
//   mass = 1        mass of each particle (kg), as the cube jelly's `mass`
//   ks, kd          spring and damper coefficients, every spring type (as the cube jelly)
//   velocity        initial velocity of every particle
// Inside test: the signed crossings of a ray along +x through each row of cell centres (a winding number along the
// ray; the rows are nudged off the lattice planes by an irrational fraction of a cell so that they miss mesh edges that
// lie on those planes). A cell is kept when its centre is inside or a triangle passes within its circumscribed sphere
// (conservative for "cut by the surface"), and always the cell of each model vertex.
// Surface: the model's vertices in its own order (surface vertex v < point count is model vertex v), then one extra
// vertex per further (vertex, UV) pair the triangles use at UV seams; SurfaceMesh::embedded holds the weights.
// A cube model with cells = n - 1 gives exactly the cube jelly of n: the same particles, order and springs.
#pragma once
#include <array>
#include <string>
#include <vector>

#include "sim/bodies/model_mesh.h"
#include "sim/body.h"

namespace wobble {

struct MeshJellyParams {
  int cells = 10;
  Placement placement;
  double mass = 1;
  double ks = 1400, kd = 50;
  Vec3 velocity = Vec3::Zero();
};

// The lattice over a model in its local frame (localPoints): cell (i, j, k) spans origin + h [i, i+1] x ...
struct LatticeFill {
  std::array<int, 3> cells{};  // cells along x, y, z
  double h = 0;                // cell edge
  Vec3 origin = Vec3::Zero();  // lowest corner
  std::vector<char> inside;    // per cell (i + cells[0] (j + cells[1] k)): centre inside the model
  std::vector<char> kept;      // per cell: inside, cut by the surface, or holding a model vertex

  int cellIndex(int i, int j, int k) const { return i + cells[0] * (j + cells[1] * k); }
};

// cells along the longest side of the local points' bounding box.
LatticeFill fillLattice(const std::vector<Vec3>& local, const std::vector<std::array<int, 3>>& triangles, int cells);

// At most (cells + 1)^3 particles and their springs, the model's vertices plus every triangle corner as surface
// vertices: an upper bound for the memory budget, counted before the lattice is built.
BodySize meshJellySize(std::int64_t cells, std::int64_t points, std::int64_t triangles);

// Throws std::length_error for more than kMaxBodyParticles particles.
Body buildMeshJelly(const std::string& name, const ModelMesh& model, const MeshJellyParams& p);

}  // namespace wobble
