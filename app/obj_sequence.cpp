#include "obj_sequence.h"

#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include <assimp/Exporter.hpp>
#include <assimp/IOStream.hpp>
#include <assimp/IOSystem.hpp>
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

// Keeps what assimp's exporter writes in memory, by path: the files are then written by the one checked writer
// (render/atomic_file.h), so a full disk is reported and no truncated OBJ or MTL ever gets its final name.
class CapturingIOSystem : public Assimp::IOSystem {
 public:
  std::map<std::string, std::string> files;

  bool Exists(const char* path) const override { return files.count(path) != 0; }
  char getOsSeparator() const override { return '/'; }
  Assimp::IOStream* Open(const char* path, const char* /*mode*/) override { return new Stream(files[path]); }
  void Close(Assimp::IOStream* stream) override { delete stream; }

 private:
  class Stream : public Assimp::IOStream {
   public:
    explicit Stream(std::string& bytes) : bytes_(bytes) { bytes_.clear(); }
    size_t Read(void*, size_t, size_t) override { return 0; }
    size_t Write(const void* data, size_t size, size_t count) override {
      bytes_.append(static_cast<const char*>(data), size * count);
      return count;
    }
    aiReturn Seek(size_t, aiOrigin) override { return aiReturn_FAILURE; }
    size_t Tell() const override { return bytes_.size(); }
    size_t FileSize() const override { return bytes_.size(); }
    void Flush() override {}

   private:
    std::string& bytes_;
  };
};

std::string readFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  if (!(in && bytes << in.rdbuf())) throw std::runtime_error(path.string() + ": cannot read");
  return bytes.str();
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
    render::writeFileAtomically(dir_ / texture_name_, readFile(*texture));
  }
}

fs::path ObjSequenceWriter::write(int frame, const SurfaceFrame& surface) const {
  const fs::path obj = dir_ / fileName(body_.name, frame, "obj"), mtl = dir_ / fileName(body_.name, frame, "mtl");
  const auto scene = makeScene(body_, surface, texture_name_);
  Assimp::Exporter exporter;
  auto* io = new CapturingIOSystem;  // owned by the exporter
  exporter.SetIOHandler(io);
  if (exporter.Export(scene.get(), "obj", obj.string()) != AI_SUCCESS)
    throw std::runtime_error("exporting " + obj.string() + ": " + exporter.GetErrorString());
  if (io->files.size() != 2 || !io->files.count(obj.string()) || !io->files.count(mtl.string()))
    throw std::runtime_error("exporting " + obj.string() + ": assimp did not produce the .obj and its .mtl");
  render::writeFileAtomically(mtl, io->files[mtl.string()]);  // the material first: an .obj in place has its .mtl
  render::writeFileAtomically(obj, io->files[obj.string()]);
  return obj;
}

}  // namespace wobble
