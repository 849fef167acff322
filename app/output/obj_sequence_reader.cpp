#include "app/output/obj_sequence_reader.h"

#include <limits>
#include <stdexcept>

#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "app/output/frame_name.h"

namespace wobble {

SurfaceFrame readObjSurface(const std::filesystem::path& obj, const SurfaceMesh& mesh) {
  const auto fail = [&](const std::string& why) { return std::runtime_error(obj.string() + ": " + why); };
  if (!std::filesystem::is_regular_file(obj)) throw fail("file not found");
  Assimp::Importer importer;
  // No post-processing: faces stay in file order and each face corner keeps its own vertex.
  const aiScene* scene = importer.ReadFile(obj.string(), 0);
  if (!scene || !scene->mRootNode) throw fail(std::string("cannot read: ") + importer.GetErrorString());
  if (scene->mNumMeshes != 1) throw fail("expected one mesh, found " + std::to_string(scene->mNumMeshes));
  const aiMesh& m = *scene->mMeshes[0];
  if (m.mNumFaces != mesh.triangles.size())
    throw fail(std::to_string(m.mNumFaces) + " faces, but the scene's body has " +
               std::to_string(mesh.triangles.size()) + " triangles (another scene or body?)");

  SurfaceFrame frame;
  frame.positions.assign(mesh.vertexCount(), Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN()));
  frame.normals.assign(mesh.vertexCount(), Eigen::Vector3f::Zero());
  for (unsigned f = 0; f < m.mNumFaces; ++f) {
    const aiFace& face = m.mFaces[f];
    if (face.mNumIndices != 3) throw fail("face " + std::to_string(f + 1) + " is not a triangle");
    for (int k = 0; k < 3; ++k) {
      const unsigned i = face.mIndices[k];
      const int vertex = mesh.triangles[f][k];
      frame.positions[vertex] = {m.mVertices[i].x, m.mVertices[i].y, m.mVertices[i].z};
      if (m.mNormals) frame.normals[vertex] = {m.mNormals[i].x, m.mNormals[i].y, m.mNormals[i].z};
    }
  }
  return frame;
}

std::filesystem::path objFramePath(const std::filesystem::path& mesh_dir, const std::string& body, int frame) {
  return mesh_dir / frameFileName(body, frame, "obj");
}

std::vector<SurfaceFrame> readObjFrame(const std::filesystem::path& mesh_dir, const SceneFile& scene, int frame,
                                       int only) {
  const auto& bodies = scene.system->bodies();
  std::vector<SurfaceFrame> surfaces(bodies.size());
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (only < 0 || int(b) == only)
      surfaces[b] = readObjSurface(objFramePath(mesh_dir, bodies[b].body.name, frame), bodies[b].body.surface);
  return surfaces;
}

}  // namespace wobble
