// Reads back a body's frame from an OBJ sequence written by ObjSequenceWriter (obj_sequence.h), through assimp, as
// the SurfaceFrame it was written from: vertex positions and normals in the body's own vertex order.
// The file's faces are the body's triangles in order, so triangle f corner k of the file gives the position and normal
// of the body's vertex triangles[f][k] (the exporter merges the jelly's seam vertices; this undoes it).
#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "app/scene/scene_file.h"
#include "sim/surface.h"

namespace wobble {

// Throws std::runtime_error naming the file when it cannot be read or does not match the topology (face count,
// triangles) of `mesh`.
SurfaceFrame readObjSurface(const std::filesystem::path& obj, const SurfaceMesh& mesh);

// MESH_DIR/<body>_NNNN.obj: frame k of a body's sequence.
std::filesystem::path objFramePath(const std::filesystem::path& mesh_dir, const std::string& body, int frame);

// Every body's surface at frame k (scene.system->bodies() order) from mesh_dir; bodies other than `only` (when >= 0)
// are left empty. Throws std::runtime_error as readObjSurface.
std::vector<SurfaceFrame> readObjFrame(const std::filesystem::path& mesh_dir, const SceneFile& scene, int frame,
                                       int only = -1);

}  // namespace wobble
