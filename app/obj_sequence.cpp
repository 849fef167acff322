#include "obj_sequence.h"

#include <cstdio>
#include <stdexcept>

#include <assimp/Exporter.hpp>
#include <assimp/material.h>
#include <assimp/scene.h>

#include "render/atomic_file.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

// An aiScene holding one triangle mesh and its material; aiScene's destructor frees what is allocated here.
std::unique_ptr<aiScene> makeScene(const Body& body, const SurfaceFrame& surface, const std::string& texture) {
  auto scene = std::make_unique<aiScene>();
  const SurfaceMesh& topology = body.surface;
  const unsigned n = static_cast<unsigned>(topology.vertexCount());

  auto* mesh = new aiMesh;
  mesh->mName = body.name;
  mesh->mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
  mesh->mNumVertices = n;
  mesh->mVertices = new aiVector3D[n];
  mesh->mNormals = new aiVector3D[n];
  mesh->mTextureCoords[0] = new aiVector3D[n];
  mesh->mNumUVComponents[0] = 2;
  for (unsigned i = 0; i < n; ++i) {
    const auto& p = surface.positions[i];
    const auto& nm = surface.normals[i];
    mesh->mVertices[i] = aiVector3D(p.x(), p.y(), p.z());
    mesh->mNormals[i] = aiVector3D(nm.x(), nm.y(), nm.z());
    mesh->mTextureCoords[0][i] = aiVector3D(topology.uv[i].x(), topology.uv[i].y(), 0);
  }
  mesh->mNumFaces = static_cast<unsigned>(topology.triangles.size());
  mesh->mFaces = new aiFace[mesh->mNumFaces];
  for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
    aiFace& face = mesh->mFaces[f];
    face.mNumIndices = 3;
    face.mIndices = new unsigned[3];
    for (int k = 0; k < 3; ++k) face.mIndices[k] = static_cast<unsigned>(topology.triangles[f][k]);
  }
  mesh->mMaterialIndex = 0;

  auto* material = new aiMaterial;
  const aiString name(body.name);
  material->AddProperty(&name, AI_MATKEY_NAME);
  // Textured: white so the texture shows its own colours; otherwise a jelly red or a cloth blue.
  const aiColor3D colour = !texture.empty() ? aiColor3D(1, 1, 1)
                           : body.kind == "cloth" ? aiColor3D(0.25f, 0.4f, 0.8f)
                                                  : aiColor3D(0.85f, 0.25f, 0.3f);
  material->AddProperty(&colour, 1, AI_MATKEY_COLOR_DIFFUSE);
  if (!texture.empty()) {
    const aiString file(texture);
    material->AddProperty(&file, AI_MATKEY_TEXTURE_DIFFUSE(0));
  }

  scene->mNumMeshes = 1;
  scene->mMeshes = new aiMesh*[1]{mesh};
  scene->mNumMaterials = 1;
  scene->mMaterials = new aiMaterial*[1]{material};
  scene->mRootNode = new aiNode(body.name);
  scene->mRootNode->mNumMeshes = 1;
  scene->mRootNode->mMeshes = new unsigned[1]{0};
  return scene;
}

}  // namespace

std::string ObjSequenceWriter::fileName(const std::string& body, int frame, std::string_view extension) {
  char number[16];
  std::snprintf(number, sizeof number, "_%04d.", frame);
  return body + number + std::string(extension);
}

ObjSequenceWriter::ObjSequenceWriter(fs::path mesh_dir, const Body& body, std::optional<fs::path> texture)
    : dir_(std::move(mesh_dir)), body_(body) {
  fs::create_directories(dir_);
  if (texture) {
    texture_name_ = texture->filename().string();
    render::writeAtomically(dir_ / texture_name_, [&](const fs::path& temp) { fs::copy_file(*texture, temp); });
  }
}

fs::path ObjSequenceWriter::write(int frame, const SurfaceFrame& surface) const {
  const fs::path partial = dir_ / ".partial";
  fs::create_directories(partial);
  const std::string obj = fileName(body_.name, frame, "obj"), mtl = fileName(body_.name, frame, "mtl");
  const auto scene = makeScene(body_, surface, texture_name_);
  Assimp::Exporter exporter;
  if (exporter.Export(scene.get(), "obj", (partial / obj).string()) != AI_SUCCESS)
    throw std::runtime_error("exporting " + (dir_ / obj).string() + ": " + exporter.GetErrorString());
  fs::rename(partial / mtl, dir_ / mtl);  // the material first: an .obj in place always has its .mtl
  fs::rename(partial / obj, dir_ / obj);
  return dir_ / obj;
}

}  // namespace wobble
