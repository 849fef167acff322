// Writes one body's surface as a numbered OBJ sequence for Blender: MESH_DIR/<body>_0001.obj with its .mtl, and the
// body's texture copied next to them (referenced by a relative path). Exported through assimp; Y up, metres.
// Each frame is exported to memory, then written under temporary names and renamed into place (.mtl first), so a
// crash or a full disk leaves no half-written frame.
// Note: assimp's OBJ exporter merges equal positions, so the jelly's face seams (one particle, several UVs) share one
// "v" line: every frame has one "v" per surface particle, in the same order.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

#include "sim/body.h"
#include "sim/surface.h"

namespace wobble {

class ObjSequenceWriter {
 public:
  // Copies the texture (if any) into mesh_dir at once.
  ObjSequenceWriter(std::filesystem::path mesh_dir, const Body& body, std::optional<std::filesystem::path> texture);

  // Writes frame (1-based) and returns the .obj path. Throws std::runtime_error on an I/O or export failure.
  std::filesystem::path write(int frame, const SurfaceFrame& surface) const;

  static std::string fileName(const std::string& body, int frame, std::string_view extension);

 private:
  std::filesystem::path dir_;
  const Body& body_;
  std::string texture_name_;  // file name in dir_, empty when untextured
};

}  // namespace wobble
