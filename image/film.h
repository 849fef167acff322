// Film: the rendered frame, linear and unclamped, with the per-pixel layers written to EXR.
//   color    mean radiance over the pixel's samples (linear RGB)
//   albedo   mean base colour at the first hit (zero where the sky shows)
//   normal   mean shading normal at the first hit, world space, turned towards the camera (not renormalised: it
//            shortens along silhouettes, as denoisers expect; zero where the sky shows)
//   depth    nearest first-hit distance along the optical axis (camera z) over the samples; +inf where every
//            sample saw the sky
//   diffuse  the part of colour that the first surface's diffuse lobe reflects (path_tracer.h); colour - diffuse is
//            the coat's reflection and the sky seen directly. The denoiser filters the two apart.
//   variance_diffuse, variance_other   estimated variance of the pixel mean's luminance, for diffuse / albedo and
//            for colour - diffuse: sample variance / samples; -1 where a pixel has a single sample
//   blur     mean over the samples of the radius in pixels over which the lens spreads the first hit (its circle of
//            confusion, camera.h; 0 for a pinhole): the denoiser mixes a blurred pixel with those in its blur
//   motion   mean over the samples of how far the first hit's image moves while the shutter is open, in pixels (x
//            right, y down; camera.h, screenMotion): zero for the sky and without motion blur. The denoiser mixes a
//            pixel so blurred with those along its motion
//   samples  samples taken in the pixel (adaptive sampling varies it)
// Pixels are stored row-major, row 0 at the top.
#pragma once
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "image/color.h"
#include "image/image.h"

namespace wobble::image {

struct Film {
  int width = 0, height = 0;
  std::vector<Color> color, albedo;
  std::vector<Eigen::Vector3f> normal;
  std::vector<float> depth;
  std::vector<Color> diffuse;
  std::vector<float> variance_diffuse, variance_other;
  std::vector<float> blur;
  std::vector<Eigen::Vector2f> motion;
  std::vector<std::uint32_t> samples;

  Film() = default;
  Film(int w, int h);
  // Sized, its colour, albedo, normal and diffuse values indeterminate (depth, variances and samples zero): for a
  // writer that sets every pixel before it reads one (the renderer at one sample per pixel, on its own threads).
  static Film unfilled(int w, int h);
  // Sets pixel i's layers as a new film starts them: no light, no surface (depth +inf), no variance estimate (-1).
  // Its sample count is the caller's.
  void clearPixel(std::size_t i) {
    color[i] = albedo[i] = normal[i] = diffuse[i] = Eigen::Vector3f::Zero();
    depth[i] = std::numeric_limits<float>::infinity();
    variance_diffuse[i] = variance_other[i] = -1.0f;
    blur[i] = 0;
    motion[i] = Eigen::Vector2f::Zero();
  }
  std::size_t index(int x, int y) const { return std::size_t(y) * width + x; }
};

// Tone maps colour (width * height values, row-major) to an 8-bit sRGB RGB image (see color.h for the curve).
Image8 develop(int width, int height, std::span<const Color> color, const ToneMap& tone_map = {});
inline Image8 develop(const Film& film, const ToneMap& tone_map = {}) {
  return develop(film.width, film.height, film.color, tone_map);
}

}  // namespace wobble::image
