#include "app/output/picture_key.h"

#include "io/content_hash.h"

namespace wobble {
namespace {

// The digest of the running program's file, once per process: a rebuilt wobble may render other pixels.
const std::string& programDigest() {
  static const std::string digest = [] {
    io::ContentHash h;
    h.addFile("/proc/self/exe");
    return h.hex();
  }();
  return digest;
}

void addVectors(io::ContentHash& h, const std::vector<Eigen::Vector3f>& v) {
  h.addArray(std::span<const float>(v.empty() ? nullptr : v.front().data(), 3 * v.size()));
}

}  // namespace

PictureKey::PictureKey(const SceneFile& scene) {
  io::ContentHash h;
  h.add(std::string_view(programDigest()));
  h.add(std::string_view(scene.picture_text));
  for (const auto& [body, file] : scene.textures) {  // a map: in name order
    h.add(std::string_view(body));
    h.addFile(file);
  }
  if (scene.render.options.environment.named()) h.addFile(scene.render.options.environment.file);
  settings_ = h.hex();
}

std::string PictureKey::frame(int frame, const render::CameraParams& camera,
                              std::span<const SurfaceFrame> surfaces) const {
  io::ContentHash h;
  h.add(std::string_view(settings_));
  h.add(frame);
  for (const Eigen::Vector3f& v : {camera.position, camera.look_at, camera.up})
    for (int k = 0; k < 3; ++k) h.add(v[k]);
  h.add(camera.vfov_deg);
  h.add(camera.width);
  h.add(camera.height);
  if (camera.aperture > 0) {  // the focus of a followed body moves with it (a pinhole's keys stay as they were)
    h.add(camera.aperture);
    h.add(camera.focus);
  }
  if (!camera.shutter_motion.isZero())  // a follow camera's motion blur (a still one's keys stay as they were)
    for (int k = 0; k < 3; ++k) h.add(camera.shutter_motion[k]);
  h.add(std::uint64_t(surfaces.size()));
  for (const SurfaceFrame& s : surfaces) {
    addVectors(h, s.positions);
    addVectors(h, s.normals);
  }
  return h.hex();
}

std::map<std::string, std::string> PictureKey::text(const std::string& frame_key) const {
  return {{kSettingsName, settings_}, {kFrameName, frame_key}};
}

}  // namespace wobble
