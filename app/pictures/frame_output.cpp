#include "app/pictures/frame_output.h"

#include <algorithm>
#include <cstdio>

#include "app/output/frame_name.h"
#include "app/output/interrupt.h"
#include "app/output/obj_sequence.h"
#include "app/output/video.h"
#include "app/pictures/frame_picture.h"
#include "image/exr_writer.h"
#include "image/png_io.h"

namespace fs = std::filesystem;

namespace wobble {

bool FrameOutput::wanted(const SceneFile& scene) { return scene.render.options.png || scene.render.options.exr; }

fs::path FrameOutput::pngPath(const fs::path& out, const std::string& scene, int frame) {
  return out / "frames" / frameFileName(scene, frame, "png");
}

fs::path FrameOutput::exrPath(const fs::path& out, const std::string& scene, int frame) {
  return out / "exr" / frameFileName(scene, frame, "exr");
}

FrameOutput::FrameOutput(const SceneFile& scene, fs::path out, bool skip_existing)
    : scene_(scene), out_(std::move(out)), render_scene_(scene), key_(scene), skip_existing_(skip_existing) {
  if (scene.render.options.png) fs::create_directories(out_ / "frames");
  if (scene.render.options.exr) fs::create_directories(out_ / "exr");
}

void FrameOutput::frame(const PosedFrame& posed) {
  std::vector<SurfaceFrame> keyed;  // every pose's surfaces
  for (const auto& pose : posed.poses) keyed.insert(keyed.end(), pose.begin(), pose.end());
  const std::string key = key_.frame(posed.frame, posed.camera, keyed);
  if (skip_existing_ && existing(posed.frame, key)) return keep(posed.frame);
  render_scene_.update(posed.times, posed.poses);
  render(posed.frame, posed.camera, key, posed.motionBlur());
}

bool FrameOutput::existing(int frame, const std::string& key) const {
  const RenderOptionsConfig& o = scene_.render.options;
  const auto has = [&](const std::map<std::string, std::string>& text) {
    const auto found = text.find(PictureKey::kFrameName);
    return found != text.end() && found->second == key;
  };
  return (!o.png || has(image::readPngText(pngPath(out_, scene_.name, frame)))) &&
         (!o.exr || has(image::readExrText(exrPath(out_, scene_.name, frame))));
}

void FrameOutput::keep(int frame) {
  ++skipped_;
  if (!scene_.render.options.png || !scene_.render.options.video) return;
  if (writing_.valid()) writing_.get();  // the video takes the frames in order
  writing_ =
      std::async(std::launch::async, [this, frame] { toVideo(image::readImage(pngPath(out_, scene_.name, frame))); });
}

void FrameOutput::toVideo(const image::Image8& image) {
  if (!video_opened_) video_ = VideoStream::open(out_ / (scene_.name + ".mp4"), image.width, image.height, scene_.fps);
  video_opened_ = true;
  if (video_) video_->write(image);
}

void FrameOutput::render(int frame, const render::CameraParams& camera, const std::string& key, bool motion_blur) {
  const FramePicture picture = renderPicture(render_scene_.scene(), camera, scene_.render.options, frame, motion_blur);
  if (writing_.valid()) writing_.get();  // the previous frame's files, and any error writing them
  writing_ = std::async(std::launch::async, [this, frame, picture, text = key_.text(key)] {
    const RenderOptionsConfig& options = scene_.render.options;
    if (options.png) {
      const image::Image8 image = developPicture(picture, options);
      image::writePng(pngPath(out_, scene_.name, frame), image, text);
      if (options.video) toVideo(image);
    }
    if (options.exr) image::writeExr(exrPath(out_, scene_.name, frame), *picture.film, *picture.denoised, text);
  });
  ++rendered_;
}

std::optional<fs::path> FrameOutput::finish() {
  if (writing_.valid()) writing_.get();
  if (!video_ || interrupted()) {
    video_.reset();  // ends ffmpeg, removes its partial file
    return std::nullopt;
  }
  return video_->finish();
}

}  // namespace wobble
