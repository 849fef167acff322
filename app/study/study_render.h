// `wobble study render`: image error against render time for the renderer's settings on one frame of a scene (a
// work-precision study, like `study accuracy` for the integrators).
// The scene is simulated up to frame K (the follow camera moves as in a run). A reference image is rendered at
// reference_spp samples per pixel as two independent halves (two noise seeds), whose mean is the reference and whose
// difference estimates the reference's own error (RMSE of the mean ~ RMSE(half a, half b) / 2); it is cached in OUT
// as reference-<key>.pfm, keyed by the scene text after overrides, the frame, the resolution and the reference
// settings, so a second study of the same frame starts at once. Then every variant renders the frame over a sweep:
// fixed-count variants at spp = 1, 2, 4, ... max_spp; adaptive ones over noise thresholds with max_spp as their
// cap and their mean samples per pixel as spp. The scene's render.sky_sampling (on when it names an environment map)
// holds in every variant and the reference; the reference's cache key holds the environment map's bytes. Gelatine
// bodies render as in a run (the camera's first gelatine hit split into its branches). Each point's error
// (image/image_error.h: RMSE of display values and relative MSE, over the frame and its worst 32 x 32 tile) and wall
// time (render plus denoising, the minimum of `repeats` runs) are recorded. Outputs: render.csv (every point),
// render.md (per variant: the fitted slope of log RMSE against log spp, where -0.5 is plain Monte Carlo and steeper is
// better; the spp and time each needs to reach given errors; every point), render.png (gnuplot: RMSE against time, and
// against spp), images/<variant>_<spp>.png of every point, and the frame itself for other renderers in frame/
// (render/scene_export.h: OBJ, JSON, baked textures; bench/cycles_compare.sh). This file runs the study into a plain
// RenderStudyResult, writing as it goes only what the renders make (the reference and its cache, images/, frame/);
// study_render_report.h writes the tables and the plot from the result.
// On a farm (farm_pieces.h): the work items are the reference's two halves (the first also exporting frame/), then
// every point in the order above; `piece` renders only its own (each piece simulates to the frame), keeping each
// image's floats and times in OUT/pieces/render/; `gather` renders nothing and measures every kept image against the
// reference: the images, errors and fits of a one-machine run (render times are each's where its piece ran).
#pragma once
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "app/study/farm_pieces.h"

namespace wobble {

struct RenderStudyOptions {
  std::filesystem::path scene = "scenes/jelly_slope.toml";
  std::vector<std::string> sets;  // KEY=VALUE scene overrides, as for `wobble run`
  int frame = 0;                  // 0: the scene's middle frame
  std::string resolution = "640x360";
  int reference_spp = 1024;
  int max_spp = 64;
  std::vector<std::string> variants;                                // empty: all (renderStudyVariants())
  std::vector<double> thresholds = {0.1, 0.05, 0.02, 0.01, 0.005};  // adaptive variants
  int repeats = 1;
  std::filesystem::path out;  // empty: out/study-render-<scene name>
  std::string gnuplot = "gnuplot";
  bool progress = true;
  std::optional<Piece> piece;  // render only this piece's work items, kept in out/pieces (out must be set)
  bool gather = false;         // render nothing: the result from every piece's items in out/pieces
};

// A named renderer setting the study sweeps.
struct RenderVariant {
  std::string name;
  std::string description;
  std::string sampler;  // "sobol" or "independent"
  bool sky_sampling = false;
  bool denoise = false;
  bool adaptive = false;  // swept over thresholds instead of spp
  int bounces = -1;       // -1: the scene's (render.bounces), as the reference
  bool mis = true;        // false: lights by light sampling alone, as before MIS
  bool roulette = false;  // Russian roulette from the second continuation on (render/path_tracer.h)
};
const std::vector<RenderVariant>& renderStudyVariants();

struct RenderPoint {
  std::string variant;
  int spp = 0;                 // fixed count, or the adaptive cap
  double threshold = 0;        // adaptive only
  double mean_spp = 0;         // samples taken / pixels
  double rays_per_sample = 0;  // camera, bounce and shadow rays
  double rmse = 0, relmse = 0, worst_tile_rmse = 0, worst_tile_relmse = 0;
  double seconds = 0, denoise_seconds = 0;
};

struct RenderVariantFit {
  std::string variant;
  double slope = 0;  // of log RMSE against log mean spp, over points above the reference's error floor (NaN if < 2)
  int points = 0;
};

struct RenderStudyResult {
  std::string scene_name;
  std::filesystem::path scene_file;
  int frame = 0, width = 0, height = 0, bounces = 0;
  int reference_spp = 0;
  double reference_seconds = 0;  // 0 when read from the cache
  bool reference_cached = false;
  std::filesystem::path reference_file;
  double reference_rmse = 0;  // estimated RMSE of the reference itself (the floor of meaningful errors)
  std::vector<RenderPoint> points;
  std::vector<RenderVariantFit> fits;
  PieceRun piece;  // with --piece: what it rendered (points and fits are then empty)
};

// Throws InputError for bad options or scene input; writes the reference and images into OUT.
RenderStudyResult runRenderStudy(const RenderStudyOptions& options);

// Slopes per variant (also used by tests on synthetic points).
std::vector<RenderVariantFit> fitRenderStudy(const std::vector<RenderPoint>& points, double floor);

}  // namespace wobble
