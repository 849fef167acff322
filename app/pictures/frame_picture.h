// FramePicture: one frame as the renderer makes it, before any file: the path-traced film of a render scene seen
// through a camera, and its denoised colour when the scene asks for denoising; developed, it is the 8-bit sRGB image
// a PNG frame holds (filmic tone curve at render.exposure). FrameOutput writes a run's frames from these, and
// `wobble compare` tiles them, so a tile is the picture a run would write at that size.
#pragma once
#include <memory>
#include <vector>

#include "app/scene/render_config.h"
#include "image/color.h"
#include "image/film.h"
#include "image/image.h"
#include "render/camera.h"
#include "render/scene.h"

namespace wobble {

struct FramePicture {
  std::shared_ptr<const image::Film> film;
  std::shared_ptr<const std::vector<image::Color>> denoised;  // empty unless render.denoise
};

// The frame number seeds the noise (render_config.h: renderSettings); motion_blur: trace each sample at its own
// instant of the shutter (render::RenderSettings::motion_blur).
FramePicture renderPicture(const render::Scene& scene, const render::CameraParams& camera,
                           const RenderOptionsConfig& options, int frame, bool motion_blur = false);
// The picture's colour (denoised when it was) as 8-bit sRGB.
image::Image8 developPicture(const FramePicture& picture, const RenderOptionsConfig& options);

}  // namespace wobble
