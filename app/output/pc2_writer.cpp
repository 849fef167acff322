#include "app/output/pc2_writer.h"

#include <string>

namespace fs = std::filesystem;

namespace wobble {

fs::path Pc2Writer::path(const fs::path& mesh_dir, const std::string& body) { return mesh_dir / (body + ".pc2"); }

Pc2Writer::Pc2Writer(fs::path file, const ObjVertexOrder& order, int start_frame)
    : order_(order), file_(std::move(file)) {
  header_.points = std::int32_t(order.size());
  header_.start_frame = float(start_frame);
  header_.sample_rate = 1;
  file_.append(encodePc2Header(header_));
}

void Pc2Writer::append(const SurfaceFrame& surface) {
  std::vector<Eigen::Vector3f> points;
  points.reserve(order_.size());
  for (const int v : order_.first_vertex) points.push_back(surface.positions[v]);
  file_.append(encodePc2Sample(points));
  ++header_.samples;
}

void Pc2Writer::finish() {
  if (header_.samples == 0) return;  // the destructor removes the temporary file
  file_.overwrite(0, encodePc2Header(header_));
  file_.commit();
}

}  // namespace wobble
