// denoise: removes Monte Carlo noise from a rendered Film with an edge-avoiding a-trous wavelet filter (Dammertz et
// al. 2010, "Edge-Avoiding A-Trous Wavelet Transform for fast Global Illumination Filtering"), steered by the pixel
// variances as in the spatial part of SVGF (Schied et al. 2017). Spatial only, so frames stay independent.
//
// The film's colour is filtered in two parts (film.h): the diffuse part divided by the albedo (the lighting, which is
// smooth across texture detail, so the cat's fur survives: it is multiplied back afterwards), and the rest (the
// coat's reflections, the sky seen directly). Each iteration i (step 2^i pixels) takes a 3 x 3 ([1 2 1] / 4) or, as
// in the paper, a 5 x 5 B3-spline kernel of taps weighted by
//   normal     max(0, n_p . n_q)^sigma_normal (as exp(-sigma_normal (1 - n_p . n_q)), its value near 1)
//   depth      exp(-|z_p - z_q| / (sigma_depth |grad z_p . (p - q)| + 1% of z_p)), z along the optical axis; sky
//              pixels (no depth) mix only with sky pixels
//   luminance  exp(-|l_p - l_q| / (sigma_luminance sqrt(3x3 Gaussian of the variance at p) + 1e-4)), the variance
//              filtered along (by the squared weights) from one iteration to the next
// Where the camera ray met gelatine first the renderer hands the gelatine's surface as the normal and depth guides
// (path_tracer.h, tracePathSplit). Depth of field: the film's blur layer (each sample's circle of confusion, pixels);
// pixels blurred by a pixel or more are filtered whole (not demodulated) and mixed with every neighbour within the
// blur of the nearer of the two, the sky included, so an out-of-focus edge is averaged rather than kept as the dither
// one lens sample a pixel leaves (filterSpan in denoiser.cpp). Motion blur alike: the film's motion layer (how far
// each sample's first hit moves on the image over the shutter, pixels); where a moving edge sweeps (a pixel next to
// one that sees the sky instead of a surface, or moves a pixel or more differently, and the pixels along its motion,
// half of it either way) pixels are filtered whole and mixed within the motion of the nearer of the two (half of it
// along the motion, all of it across), so a fast edge is averaged rather than dithered by one instant a pixel.
// Well-sampled pixels (at least `well_sampled` samples, as adaptive sampling gives where the light is noisy, such as
// the sky-lit shade under a cloth) are changed by the first `well_sampled_iterations` iterations only (a reach of 3
// pixels with the 3 x 3 kernel): their own noise is already small, and the wide iterations only add bias there. Their
// taps 4 to 16 pixels away land on the same floor across a narrow shade and past a silhouette, and the luminance
// weight lets them in where the variance is large: in dim light each sample's share of sky or of a sunlit surface
// seen through a gap is a large part of the pixel, and at a silhouette the pixel's coverage adds its own spread: they
// would lift a thin shadow (the contact shadow under a draped cloth's hem, by up to 0.19 of full scale). The reach
// following the sample count is the idea of Rousselle, Knaus and Zwicker 2011 (a filter scale per pixel from its error
// estimate), reduced to one step. Lens- and motion-blurred pixels keep every iteration (their blur is the filter's to spread).
// Parameters (DenoiseSettings): iterations, radius (1: 3 x 3 kernel, 2: 5 x 5; the filter reaches
// radius (2^iterations - 1) pixels), sigma_luminance, sigma_normal, sigma_depth, well_sampled (0: off),
// well_sampled_iterations. Deterministic: every output pixel is a fixed sum over its neighbours.
#pragma once
#include <vector>

#include "image/film.h"
#include "render/color.h"

namespace wobble::render {

struct DenoiseSettings {
  int iterations = 5;
  int radius = 1;
  float sigma_luminance = 4;
  float sigma_normal = 128;
  float sigma_depth = 1;
  int well_sampled = 16;  // samples from which a pixel takes only the first iterations; 0: every pixel takes all
  int well_sampled_iterations = 2;
};

// The denoised colour, one per pixel (row-major, as film.color). Throws std::invalid_argument on an inconsistent
// film or settings out of range.
std::vector<Color> denoise(const image::Film& film, const DenoiseSettings& settings = {});

}  // namespace wobble::render
