// FLIP: the difference evaluator for alternating images of Andersson, Nilsson, Akenine-Möller, Oskarsson, Åström and
// Fairchild, "FLIP: A Difference Evaluator for Alternating Images", Proc. ACM Comput. Graph. Interact. Tech. 3(2),
// 2020 (HPG 2020), and its HDR extension, Andersson, Nilsson, Shirley and Akenine-Möller, "Visualizing Errors in
// Rendered High Dynamic Range Images", Eurographics 2021 short papers. Written here from the papers (no FLIP library
// is packaged for Debian 12); docs/rendering-tests.md says how it was checked.
//
// LDR-FLIP (display images: sRGB-encoded values in [0, 1], PNG): per pixel, in [0, 1], 0 where the images agree.
//   Colour:   sRGB -> linear -> XYZ -> YyCxCz; each channel blurred by the contrast sensitivity filters of the
//             observer (sums of Gaussians, achromatic b = 0.0047, red-green 0.0053, blue-yellow 34.1 / 13.5 with
//             0.04 / 0.025, in degrees^2); back to linear RGB clamped to [0, 1]; CIELAB with the Hunt adjustment
//             (a*, b* times 0.01 L*); HyAB distance |dL| + |d(a, b)|; raised to q_c = 0.7 and remapped so that
//             p_c = 0.4 of the largest distance (green against blue) maps to p_t = 0.95.
//   Features: edges and points of the achromatic channel (first and second derivatives of a Gaussian whose two
//             standard deviations span w = 0.082 degrees), differences of their magnitudes, (d / sqrt 2)^q_f with
//             q_f = 0.5.
//   Error:    colour ^ (1 - features).
// HDR-FLIP (linear images: EXR, HDR, PFM): the images exposed at 2^e and tone mapped (ACES filmic fit) for exposures
//   e from start to stop in whole stops (at least 2), the start putting the reference's brightest luminance at 0.85
//   of the tone curve's output, the stop its median; the per-pixel maximum of LDR-FLIP over the exposures.
// pixels_per_degree: the observer; the default 67 is a 0.7 m wide 4K display seen from 0.7 m (the papers' default).
// Both images must be of the same size; the first three channels are colour (one channel: grey), alpha is ignored.
// Borders are extended by their edge pixels.
#pragma once
#include <vector>

#include "image/image.h"

namespace wobble::image {

inline constexpr double kFlipDefaultPixelsPerDegree = 0.7 * 3840 / 0.7 * 3.14159265358979323846 / 180;

// One channel, width x height, each pixel in [0, 1]. Throws std::invalid_argument when the sizes differ.
ImageF ldrFlip(const ImageF& reference, const ImageF& test, double pixels_per_degree = kFlipDefaultPixelsPerDegree);
ImageF hdrFlip(const ImageF& reference, const ImageF& test, double pixels_per_degree = kFlipDefaultPixelsPerDegree);

// The exposures HDR-FLIP uses for a reference (stops): start, stop and their count.
struct FlipExposures {
  double start = 0, stop = 0;
  int count = 2;
};
FlipExposures hdrFlipExposures(const ImageF& reference);

// The pooled values the FLIP tool prints: mean, the weighted median and quartiles (the error below which that share
// of the total error lies), min, max; and plain percentiles of the pixels' errors.
struct FlipStats {
  double mean = 0, weighted_median = 0, weighted_q1 = 0, weighted_q3 = 0, min = 0, max = 0;
  double p50 = 0, p95 = 0, p99 = 0;
};
FlipStats flipStats(const ImageF& error_map);
// The q-th percentile (0..100) of the errors, linearly interpolated between ranks.
double flipPercentile(const ImageF& error_map, double q);

// An error map (values in [0, 1], one channel) as the papers show it: the magma colour map (matplotlib's, CC0), RGB.
Image8 magmaHeatmap(const ImageF& error_map);

}  // namespace wobble::image
