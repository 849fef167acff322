// Reads a user's triangle model (`mesh = "..."` of a mesh jelly or a mesh collider) into a ModelMesh
// (sim/bodies/model_mesh.h), and the keys that place it.
// OBJ is read here, line by line, so that the points are the file's `v` lines in order and count (what a Mesh Cache
// modifier in Blender needs); polygons become triangle fans, `vt` give the corners' UVs. Every other format assimp
// reads (PLY, STL, glTF, ...) goes through assimp, triangulated, with points of equal position welded in the order
// assimp gives them (STL repeats a point for each triangle).
#pragma once
#include <cstdint>
#include <filesystem>
#include <string>

#include "sim/bodies/model_mesh.h"

namespace wobble {

class TableReader;

// A model of more triangles is refused (the closest-point and fill costs grow with it; a 20k-triangle model is small).
inline constexpr std::int64_t kMaxModelTriangles = 2'000'000;

// Throws std::runtime_error saying what is wrong (unreadable, not a mesh, a bad line with its number, too many
// triangles); the caller names the file and key.
ModelMesh readModelFile(const std::filesystem::path& path);

// Reads `mesh` (relative to the scene file), checks it (checkModel, closed or not) and fails at `mesh` naming the
// file and the problem.
ModelMesh readModelKey(TableReader& r, bool closed);

// The most a placed model may span (its bounding box's longest side times `scale`): far beyond any scene wobble
// simulates (centimetres to metres), and far below where the lattice's cell arithmetic and squared lengths overflow.
inline constexpr double kMaxPlacedModelSpan = 1e6;  // metres

// Reads center (default `center`), scale (> 0, and at most what keeps `model` within kMaxPlacedModelSpan),
// rotation_axis, rotation_deg.
Placement readPlacement(TableReader& r, const Vec3& center, const ModelMesh& model);

}  // namespace wobble
