#include "app/output/obj_sequence.h"

#include <cstdio>
#include <stdexcept>

#include "app/output/frame_name.h"
#include "app/output/obj_text.h"
#include "io/atomic_file.h"
#include "io/text_file.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

ObjMaterial materialOf(const Body& body, const std::optional<fs::path>& texture, const BodyLook& look) {
  return {body.name, look.color, texture ? texture->filename().string() : "", look.material == "jelly"};
}

}  // namespace

std::uint64_t ObjSequenceWriter::frameSizeBound(const Body& body, const ObjVertexOrder& order,
                                                const std::optional<fs::path>& texture, const BodyLook& look,
                                                int frame) {
  return mtlText(materialOf(body, texture, look)).size() +
         objTextSizeBound(body.name, body.surface, order, frameFileName(body.name, frame, "mtl"));
}

fs::path ObjSequenceWriter::basePath(const fs::path& mesh_dir, const std::string& body) {
  return mesh_dir / (body + ".obj");
}

ObjSequenceWriter::ObjSequenceWriter(fs::path mesh_dir, const Body& body, std::optional<fs::path> texture,
                                     const BodyLook& look)
    : dir_(std::move(mesh_dir)), body_(body), order_(body.surface) {
  material_ = materialOf(body, texture, look);
  fs::create_directories(dir_);
  if (texture) io::writeFileAtomically(dir_ / material_.texture, io::readTextFile(*texture));
}

fs::path ObjSequenceWriter::write(int frame, const SurfaceFrame& surface) const {
  return writeFiles(dir_ / frameFileName(body_.name, frame, "obj"), surface);
}

fs::path ObjSequenceWriter::writeBase(const SurfaceFrame& surface) const {
  return writeFiles(basePath(dir_, body_.name), surface);
}

fs::path ObjSequenceWriter::writeFiles(const fs::path& obj, const SurfaceFrame& surface) const {
  fs::path mtl = obj;
  mtl.replace_extension(".mtl");
  io::writeFileAtomically(mtl, mtlText(material_));  // the material first: an .obj in place has its .mtl
  io::writeFileAtomically(obj, objText(body_.name, body_.surface, order_, surface, mtl.filename().string()));
  return obj;
}

}  // namespace wobble
