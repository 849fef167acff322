// EnvironmentMap: image-based light. Radiance arriving from every direction, read from an equirectangular
// (latitude-longitude) image that surrounds the scene at infinity; it replaces the gradient sky (lights.h: Background).
//
//   image     linear radiance (a Radiance .hdr or OpenEXR .exr file), width = 2 x height. Row 0 (the top) looks
//             straight up (+Y, the world's up), the last row straight down; the image's centre column looks along +X,
//             a quarter of the width right of it along +Z, so (u, v) in [0, 1)^2 from the top left is the direction
//             with polar angle theta = pi v from +Y and azimuth atan2(z, x) = 2 pi u - pi. This is Blender's
//             Environment Texture under wobble's axes (Blender's (x, y, z) = wobble's (x, -z, y)), so `wobble blend`
//             hands the same file to Cycles unchanged. Each texel is constant over its patch of directions (nearest
//             texel, Cycles' "Closest" interpolation), so the map is exactly the piecewise-constant function its
//             sampling density follows.
//   rotation  degrees about the up axis, counterclockwise seen from above (right-handed about +Y): at 90, what was
//             seen looking along +Z is seen along +X. Cycles: a Mapping node of type Texture rotating about Z by the
//             same angle.
//   strength  multiplies the image's radiance (>= 0; Cycles' Background strength).
//
// Sampling (next-event estimation of the environment, combined with BSDF sampling by MIS in the path tracer): a texel
// is drawn with probability in proportion to its luminance times its solid angle (2 pi / W)(cos theta0 - cos theta1)
// by a 2D piecewise-constant distribution (pbrt-v4's PiecewiseConstant2D: Pharr, Jakob, Humphreys, "Physically Based
// Rendering", 4th ed., 2023, section 12.5.2, Image Infinite Lights; the solid angle is the exact form of the sin theta
// factor of its latitude-longitude version, 3rd ed., section 14.2.4), then a direction uniformly within the texel's
// patch (uniform in azimuth and cos theta). The density is then constant over each texel: luminance / (the map's
// luminance integrated over the sphere), so light / pdf is the same for every direction of a texel, and a map of one
// luminance is sampled with no variance at all.
#pragma once
#include <filesystem>
#include <vector>

#include <Eigen/Core>

#include "image/image.h"
#include "render/color.h"
#include "render/piecewise_constant.h"

namespace wobble::render {

class EnvironmentMap {
 public:
  // rgb: 1 (grey) or 3 (RGB) channels of linear radiance, width = 2 x height; negative values (ringing of some
  // filters) count as 0. Throws std::invalid_argument on another shape, a non-finite value, a negative or non-finite
  // strength, a non-finite rotation.
  EnvironmentMap(const image::ImageF& rgb, float rotation_deg, float strength, std::filesystem::path file = {});
  // Reads an HDR or EXR file (image/image_file.h): throws ImageFileError (unreadable, too large) or
  // std::invalid_argument (not linear radiance, not 2:1, a value out of range) naming the file.
  static EnvironmentMap load(const std::filesystem::path& file, float rotation_deg, float strength);

  // Radiance arriving along -d (seen looking along the unit direction d), times the strength.
  Color eval(const Eigen::Vector3f& d) const;
  bool empty() const { return !(total_ > 0); }  // black: nothing to sample
  // A unit direction for (u1, u2) in [0, 1)^2 and its solid-angle density (0 only for an empty map).
  Eigen::Vector3f sample(float u1, float u2, float& pdf) const;
  float pdf(const Eigen::Vector3f& d) const;

  int width() const { return width_; }
  int height() const { return height_; }
  float rotationDeg() const { return rotation_deg_; }
  float strength() const { return strength_; }
  const std::filesystem::path& file() const { return file_; }  // empty when built from an image in memory

 private:
  int texel(const Eigen::Vector3f& d) const;  // index of the texel d looks at
  float texelSolidAngle(int row) const;

  int width_ = 0, height_ = 0;
  float rotation_deg_ = 0, strength_ = 1;
  float cos_rotation_ = 1, sin_rotation_ = 0;
  std::filesystem::path file_;
  std::vector<Color> radiance_;   // times the strength, row after row from the top
  std::vector<float> cos_theta_;  // height + 1 row boundaries, from 1 (up) to -1 (down)
  PiecewiseConstant2D distribution_;
  double total_ = 0;  // luminance x solid angle over all texels
};

}  // namespace wobble::render
