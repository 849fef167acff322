#include "app/view/frame_output.h"

#include <cstdio>

#include "app/output/frame_name.h"
#include "app/output/interrupt.h"
#include "app/output/obj_sequence.h"
#include "app/output/video.h"
#include "app/view/frame_picture.h"
#include "render/image/exr_writer.h"
#include "render/image/png_io.h"

namespace fs = std::filesystem;

namespace wobble {

bool FrameOutput::wanted(const SceneFile& scene) { return scene.render.options.png || scene.render.options.exr; }

fs::path FrameOutput::pngPath(const fs::path& out, const std::string& scene, int frame) {
  return out / "frames" / frameFileName(scene, frame, "png");
}

fs::path FrameOutput::exrPath(const fs::path& out, const std::string& scene, int frame) {
  return out / "exr" / frameFileName(scene, frame, "exr");
}

FrameOutput::FrameOutput(const SceneFile& scene, fs::path out)
    : scene_(scene), out_(std::move(out)), render_scene_(scene), rig_(scene) {
  if (scene.render.options.png) fs::create_directories(out_ / "frames");
  if (scene.render.options.exr) fs::create_directories(out_ / "exr");
}

void FrameOutput::observe(int frame, const VecX& x) { rig_.observe(frame, *scene_.system, x); }

void FrameOutput::frame(int frame, std::span<const SurfaceFrame> surfaces, bool write) {
  if (rig_.followedBody() >= 0) rig_.observe(frame, surfaces[rig_.followedBody()]);
  if (!write) return;
  render_scene_.update(scene_.frameTime(frame), surfaces);
  render(frame);
}

void FrameOutput::render(int frame) {
  const FramePicture picture = renderPicture(render_scene_.scene(), rig_.params(), scene_.render.options, frame);
  if (writing_.valid()) writing_.get();  // the previous frame's files, and any error writing them
  writing_ = std::async(std::launch::async, [this, frame, picture] {
    const RenderOptionsConfig& options = scene_.render.options;
    if (options.png) {
      const render::Image8 image = developPicture(picture, options);
      render::writePng(pngPath(out_, scene_.name, frame), image);
      if (options.video) {
        if (!video_opened_) video_ = VideoStream::open(out_ / (scene_.name + ".mp4"), image.width, image.height, scene_.fps);
        video_opened_ = true;
        if (video_) video_->write(image);
      }
    }
    if (options.exr) render::writeExr(exrPath(out_, scene_.name, frame), *picture.film, *picture.denoised);
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
