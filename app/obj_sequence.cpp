#include "obj_sequence.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "obj_text.h"
#include "render/atomic_file.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

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

fs::path ObjSequenceWriter::basePath(const fs::path& mesh_dir, const std::string& body) {
  return mesh_dir / (body + ".obj");
}

ObjSequenceWriter::ObjSequenceWriter(fs::path mesh_dir, const Body& body, std::optional<fs::path> texture,
                                     const BodyLook& look)
    : dir_(std::move(mesh_dir)), body_(body), order_(body.surface) {
  material_ = {body.name, look.color, "", look.material == "jelly"};
  fs::create_directories(dir_);
  if (texture) {
    material_.texture = texture->filename().string();
    render::writeFileAtomically(dir_ / material_.texture, readFile(*texture));
  }
}

fs::path ObjSequenceWriter::write(int frame, const SurfaceFrame& surface) const {
  return writeFiles(dir_ / fileName(body_.name, frame, "obj"), surface);
}

fs::path ObjSequenceWriter::writeBase(const SurfaceFrame& surface) const {
  return writeFiles(basePath(dir_, body_.name), surface);
}

fs::path ObjSequenceWriter::writeFiles(const fs::path& obj, const SurfaceFrame& surface) const {
  fs::path mtl = obj;
  mtl.replace_extension(".mtl");
  render::writeFileAtomically(mtl, mtlText(material_));  // the material first: an .obj in place has its .mtl
  render::writeFileAtomically(obj, objText(body_.name, body_.surface, order_, surface, mtl.filename().string()));
  return obj;
}

}  // namespace wobble
