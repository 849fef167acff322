// A variant's tile in `wobble compare`'s video, frame by frame: which of its pictures it shows, and its label.
// The label, top left over a shaded box: the variant ("rk4, dt = 1.2e-3, ks = 5e4") and under it the simulated
// time ("t = 1.23 s"), and, in colour, what went wrong:
//   - "t = 4.97 s, lost its shape at 0.43 s (strain 0.576 > 0.5)" (orange) from the first frame whose largest spring
//     strain passed the stability study's bound;
//   - "blew up at t = 0.84 s (step 700)" (red) from the first frame the run did not reach; the tile then keeps the
//     last frame it reached.
#pragma once
#include <optional>
#include <string>

#include "image/compose.h"
#include "image/font.h"
#include "image/image.h"

namespace wobble {

struct VariantTrack {
  int first_frame = 1;  // the comparison's first frame (--frames A:B)
  int last_frame = 0;   // the last frame the run reached and wrote; below first_frame: none
  std::optional<double> blow_up_time;
  long blow_up_step = 0;
  std::optional<int> lost_shape_frame;                                  // first frame with the strain over the bound
  double lost_shape_time = 0, lost_shape_strain = 0, strain_bound = 0;  // at that frame
};

struct TileView {
  int picture = 0;  // the frame whose picture the tile shows: this one, the last one reached (frozen), or 0 (none)
  bool frozen = false;
  std::string status;
  image::Rgb8 color{255, 255, 255};
};

inline constexpr image::Rgb8 kLostShapeColor{255, 170, 40};
inline constexpr image::Rgb8 kBlewUpColor{255, 60, 60};

// Frame `frame`, at simulated time `time`.
TileView tileView(const VariantTrack& track, int frame, double time);

// A number as people write it in reports: 1.2e-3, 5e4, 1400, 0.033 (3 significant digits at most).
std::string shortNumber(double x);
// Seconds for a label: 0.84, 12.30; two significant digits below 0.1 (0.0036).
std::string labelSeconds(double t);

// The label's pixel height for a tile this tall (9 at least, so that tiny test tiles still get readable text).
float labelPixels(int tile_height);
// Draws the label of `view` (title over its status) on the tile.
void drawLabel(image::Image8& tile, const image::Font& font, const std::string& title, const TileView& view);

}  // namespace wobble
