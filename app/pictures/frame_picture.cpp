#include "app/pictures/frame_picture.h"

#include "render/denoiser.h"
#include "render/renderer.h"

namespace wobble {

FramePicture renderPicture(const render::Scene& scene, const render::CameraParams& camera,
                           const RenderOptionsConfig& options, int frame, bool motion_blur) {
  render::RenderSettings settings = renderSettings(options, frame);
  settings.motion_blur = motion_blur;
  auto film = std::make_shared<image::Film>(render::render(scene, render::Camera(camera), settings));
  auto denoised = std::make_shared<std::vector<image::Color>>();
  if (options.denoise) *denoised = render::denoise(*film);
  return {std::move(film), std::move(denoised)};
}

image::Image8 developPicture(const FramePicture& picture, const RenderOptionsConfig& options) {
  image::ToneMap tone;
  tone.exposure = static_cast<float>(options.exposure);
  const std::span<const image::Color> color = options.denoise ? *picture.denoised : picture.film->color;
  return image::develop(picture.film->width, picture.film->height, color, tone);
}

}  // namespace wobble
