#include "app/scene/model_file.h"

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>
#include <charconv>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

#include "app/scene/table_reader.h"
#include "io/number_text.h"

namespace wobble {
namespace fs = std::filesystem;
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

void checkTriangleCount(std::size_t n) {
  if (std::int64_t(n) > kMaxModelTriangles)
    throw std::runtime_error("it has more than " + std::to_string(kMaxModelTriangles) + " triangles");
}

// An OBJ index (1-based, or negative: counted back from the last one read) as 0-based.
int objIndex(const std::string& token, std::size_t count, int line, const char* what) {
  long value = 0;
  const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || end != token.data() + token.size() || value == 0)
    throw std::runtime_error("line " + std::to_string(line) + ": '" + token + "' is not a " + what + " index");
  const long index = value > 0 ? value - 1 : long(count) + value;
  if (index < 0 || index >= long(count))
    throw std::runtime_error("line " + std::to_string(line) + ": " + what + " index " + token + " is out of range (" +
                             std::to_string(count) + " read so far)");
  return static_cast<int>(index);
}

ModelMesh readObj(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("cannot open it");
  ModelMesh m;
  std::vector<Eigen::Vector2f> uvs;
  bool any_uv = true;
  std::string text;
  for (int line = 1; std::getline(in, text); ++line) {
    std::istringstream s(text);
    std::string tag;
    s >> tag;
    if (tag == "v") {
      Vec3 p;
      std::string c[3];
      s >> c[0] >> c[1] >> c[2];
      for (int a = 0; a < 3; ++a) {
        try {
          std::size_t used = 0;
          p[a] = std::stod(c[a], &used);
          if (used != c[a].size()) throw std::invalid_argument("");
        } catch (const std::out_of_range&) {
          p[a] = std::numeric_limits<double>::infinity();
        } catch (const std::invalid_argument&) {
          throw std::runtime_error("line " + std::to_string(line) + ": a `v` line needs three numbers");
        }
      }
      m.points.push_back(p);
    } else if (tag == "vt") {
      float u = 0, v = 0;
      s >> u >> v;
      uvs.emplace_back(u, v);
    } else if (tag == "f") {
      std::vector<std::pair<int, int>> corners;  // (point, uv or -1)
      std::string token;
      while (s >> token) {
        const std::size_t slash = token.find('/');
        const int point = objIndex(token.substr(0, slash), m.points.size(), line, "vertex");
        int uv = -1;
        if (slash != std::string::npos) {
          const std::size_t slash2 = token.find('/', slash + 1);
          const std::string t =
              token.substr(slash + 1, slash2 == std::string::npos ? std::string::npos : slash2 - slash - 1);
          if (!t.empty()) uv = objIndex(t, uvs.size(), line, "texture coordinate");
        }
        corners.emplace_back(point, uv);
      }
      if (corners.size() < 3)
        throw std::runtime_error("line " + std::to_string(line) + ": a face needs at least 3 vertices");
      for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
        const std::array<std::pair<int, int>, 3> tri{corners[0], corners[k], corners[k + 1]};
        m.triangles.push_back({tri[0].first, tri[1].first, tri[2].first});
        std::array<Eigen::Vector2f, 3> uv;
        for (int c = 0; c < 3; ++c) {
          any_uv = any_uv && tri[c].second >= 0;
          uv[c] = tri[c].second >= 0 ? uvs[tri[c].second] : Eigen::Vector2f::Zero();
        }
        m.corner_uv.push_back(uv);
      }
      checkTriangleCount(m.triangles.size());
    }
  }
  if (!any_uv) m.corner_uv.clear();
  return m;
}

ModelMesh readWithAssimp(const fs::path& path) {
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path.string(), aiProcess_Triangulate | aiProcess_SortByPType);
  if (!scene) throw std::runtime_error(importer.GetErrorString());
  ModelMesh m;
  std::map<std::array<double, 3>, int> weld;
  bool any_uv = true;
  for (unsigned i = 0; i < scene->mNumMeshes; ++i) {
    const aiMesh* mesh = scene->mMeshes[i];
    if (!(mesh->mPrimitiveTypes & aiPrimitiveType_TRIANGLE)) continue;
    std::vector<int> point(mesh->mNumVertices);
    for (unsigned v = 0; v < mesh->mNumVertices; ++v) {
      const aiVector3D& p = mesh->mVertices[v];
      const auto [it, added] = weld.try_emplace({p.x, p.y, p.z}, int(m.points.size()));
      if (added) m.points.emplace_back(p.x, p.y, p.z);
      point[v] = it->second;
    }
    for (unsigned f = 0; f < mesh->mNumFaces; ++f) {
      const aiFace& face = mesh->mFaces[f];
      if (face.mNumIndices != 3) continue;
      std::array<Eigen::Vector2f, 3> uv;
      for (int c = 0; c < 3; ++c) {
        const unsigned v = face.mIndices[c];
        uv[c] = mesh->HasTextureCoords(0) ? Eigen::Vector2f(mesh->mTextureCoords[0][v].x, mesh->mTextureCoords[0][v].y)
                                          : Eigen::Vector2f::Zero();
      }
      any_uv = any_uv && mesh->HasTextureCoords(0);
      m.triangles.push_back({point[face.mIndices[0]], point[face.mIndices[1]], point[face.mIndices[2]]});
      m.corner_uv.push_back(uv);
    }
    checkTriangleCount(m.triangles.size());
  }
  if (!any_uv) m.corner_uv.clear();
  return m;
}

}  // namespace

ModelMesh readModelFile(const fs::path& path) {
  if (lower(path.extension().string()) == ".obj") return readObj(path);
  return readWithAssimp(path);
}

ModelMesh readModelKey(TableReader& r, bool closed) {
  const auto name = r.optionalString("mesh");
  if (!name) r.fail("mesh", "is required: the path of a triangle mesh file (OBJ, PLY, STL, glTF)");
  const fs::path path = r.filePath("mesh", *name);
  if (!fs::is_regular_file(path)) r.fail("mesh", "file not found: " + path.string());
  ModelMesh model;
  try {
    model = readModelFile(path);
  } catch (const std::exception& e) {
    r.fail("mesh", "cannot read " + path.string() + ": " + e.what());
  }
  if (const std::string problem = checkModel(model, closed); !problem.empty())
    r.fail("mesh", path.string() + ": " + problem);
  return model;
}

Placement readPlacement(TableReader& r, const Vec3& center, const ModelMesh& model) {
  Placement p;
  p.center = r.vec3("center", center);
  p.scale = r.number("scale", p.scale, Range::positive());
  Eigen::AlignedBox3d box;
  for (const Vec3& point : model.points) box.extend(point);
  const double span = box.sizes().maxCoeff();  // > 0: checkModel refuses a degenerate model
  if (!(p.scale * span <= kMaxPlacedModelSpan))
    r.fail("scale", "scales the model (" + io::formatNumber(span, 4) + " m across) to " +
                        io::formatNumber(p.scale * span, 4) + " m; allowed: at most " +
                        io::formatNumber(kMaxPlacedModelSpan, 4) +
                        " m, scale <= " + io::formatNumber(kMaxPlacedModelSpan / span, 4));
  p.rotation_axis = r.vec3("rotation_axis", p.rotation_axis);
  p.rotation_deg = r.number("rotation_deg", p.rotation_deg);
  if (p.rotation_deg != 0 && p.rotation_axis.norm() == 0) r.fail("rotation_axis", "must not be zero");
  return p;
}

}  // namespace wobble
