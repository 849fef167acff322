// cie76: how far apart two display images are in colour, as a person compares them side by side. Each pixel's 8-bit
// sRGB code is decoded to linear Rec.709, taken to CIE XYZ (D65) and to CIE L*a*b* (CIE 15:2004, D65 white); the
// difference of a pixel is Delta E*ab (CIE76): the Euclidean distance in L*a*b*. About 2.3 is a just-noticeable
// difference (Sharma, Digital Color Imaging Handbook, 2003). `wobble blend`'s Cycles pictures are measured against
// wobble's own with it (docs/blender.md); bench/cie76 prints it for two PNG files.
// Parameters: a, b (the same size, 3 or 4 channels: RGB, alpha ignored).
#pragma once
#include <cstdint>

#include <Eigen/Core>

#include "image/image.h"

namespace wobble::image {

struct ColorDifference {
  double mean = 0;  // over every pixel
  double p95 = 0;   // the 95th percentile of the pixels' differences
  double max = 0;
};

// Throws std::invalid_argument when the sizes differ or an image has fewer than 3 channels.
ColorDifference cie76(const Image8& a, const Image8& b);

// L*a*b* (D65) of an 8-bit sRGB colour.
Eigen::Vector3d srgb8ToLab(std::uint8_t r, std::uint8_t g, std::uint8_t b);

}  // namespace wobble::image
