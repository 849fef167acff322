// Pc2Writer: one body's surface over a run as a PC2 point cache (pc2.h), MESH_DIR/<body>.pc2, for Blender's Mesh
// Cache modifier on the base mesh MESH_DIR/<body>.obj (obj_sequence.h). Points in ObjVertexOrder, the base OBJ's
// `v` order; one sample per frame written, the first at `start_frame`; float32, Y up, metres.
// Written frame by frame under a temporary name (a long run's cache is never held in memory) and renamed by
// finish(), after the sample count in the header is set to the frames written: a run that blows up or is interrupted
// keeps a valid PC2 of its frames. Destroyed without finish() (an I/O error), it leaves no file.
#pragma once
#include <filesystem>

#include "app/output/obj_vertex_order.h"
#include "app/output/pc2.h"
#include "io/atomic_file.h"
#include "sim/surface.h"

namespace wobble {

class Pc2Writer {
 public:
  Pc2Writer(std::filesystem::path file, const ObjVertexOrder& order, int start_frame);

  void append(const SurfaceFrame& surface);
  // With no frame appended there is nothing to play: no file. Throws std::runtime_error on an I/O failure.
  void finish();

  static std::filesystem::path path(const std::filesystem::path& mesh_dir, const std::string& body);

 private:
  const ObjVertexOrder& order_;
  Pc2Header header_;
  io::AtomicFileWriter file_;
};

}  // namespace wobble
