// Writes one body's surface as OBJ files for Blender: a numbered sequence MESH_DIR/<body>_0001.obj, ... and, for the
// PC2 point cache (pc2_writer.h), one base mesh MESH_DIR/<body>.obj; each with its .mtl (the scene's colour and
// texture, obj_text.h), and the body's texture copied next to them (referenced by a relative path). Y up, metres.
// Every file of a body has the same `v` lines in the same order (ObjVertexOrder: one per surface particle).
// Each file is made in memory, then written under a temporary name and renamed into place (.mtl first), so a crash
// or a full disk leaves no half-written file.
#pragma once
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

#include "app/output/obj_text.h"
#include "app/output/obj_vertex_order.h"
#include "app/scene/render_config.h"
#include "sim/body.h"
#include "sim/surface.h"

namespace wobble {

class ObjSequenceWriter {
 public:
  // Copies the texture (if any) into mesh_dir at once.
  ObjSequenceWriter(std::filesystem::path mesh_dir, const Body& body, std::optional<std::filesystem::path> texture,
                    const BodyLook& look);

  // Writes frame (1-based) and returns the .obj path. Throws std::runtime_error on an I/O failure.
  std::filesystem::path write(int frame, const SurfaceFrame& surface) const;
  // Writes the point cache's base mesh, <body>.obj, and returns its path.
  std::filesystem::path writeBase(const SurfaceFrame& surface) const;

  const ObjVertexOrder& order() const { return order_; }

  // The most bytes write(frame, ...) writes, the OBJ and its MTL, whatever the body's positions (objTextSizeBound).
  static std::uint64_t frameSizeBound(const Body& body, const ObjVertexOrder& order,
                                      const std::optional<std::filesystem::path>& texture, const BodyLook& look,
                                      int frame);

  static std::filesystem::path basePath(const std::filesystem::path& mesh_dir, const std::string& body);

 private:
  std::filesystem::path writeFiles(const std::filesystem::path& obj, const SurfaceFrame& surface) const;

  std::filesystem::path dir_;
  const Body& body_;
  ObjVertexOrder order_;
  ObjMaterial material_;  // its texture: a file name in dir_, empty when untextured
};

}  // namespace wobble
