// The renderer's radiance type and colour transforms: those of the pictures (image/color.h), named here so that the
// renderer's code says Color, luminance and ToneMap as its own.
#pragma once
#include "image/color.h"

namespace wobble::render {

using image::Color;
using image::linearToSrgb;
using image::linearToSrgb8;
using image::luminance;
using image::srgb8ToLinear;
using image::srgbToLinear;
using image::ToneMap;

}  // namespace wobble::render
