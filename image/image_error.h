// imageError: how far a rendered image is from a reference of the same view (the render study's yardstick).
//   rmse            root mean square difference of the display values: each linear colour through the tone map and
//                   the sRGB encoding to [0, 1] (what the PNG shows, before rounding to 8 bits), over every channel
//   relmse          relative MSE of the linear colours (Rousselle et al. 2011): mean of (x - r)^2 / (r^2 + 0.01)
//   worst_tile_*    the same over the worst tile_size x tile_size tile (tiles cut at the image's right and bottom
//                   edges count if at least half a tile): where the noise is, not just how much there is on average
// Parameters: width, height; image and reference (width * height linear colours each), tone_map, tile_size (> 0).
#pragma once
#include <span>

#include "image/color.h"

namespace wobble::image {

struct ImageError {
  double rmse = 0, relmse = 0;
  double worst_tile_rmse = 0, worst_tile_relmse = 0;
};

// Throws std::invalid_argument on mismatched sizes.
ImageError imageError(int width, int height, std::span<const Color> image, std::span<const Color> reference,
                      const ToneMap& tone_map = {}, int tile_size = 32);

}  // namespace wobble::image
