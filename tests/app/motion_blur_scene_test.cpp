// Motion blur through `wobble run` (camera.shutter): a blurred frame is the time average of the poses the shutter
// saw, over [t - shutter / fps, t], closing at the frame. Oracle: the same run at four times the frame rate without
// blur, whose stills at the shutter's times, averaged (trapezoid rule), are that integral. A jelly falls freely past
// a fixed camera, about twice its own height during the shutter: a frame without blur, or blurred over the wrong
// interval (after the frame, or a shorter one), lies far from the average.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "image/image_file.h"
#include "tests/app/output_check.h"
#include "tests/app/scratch_dir.h"

namespace fs = std::filesystem;

namespace wobble {
namespace {

class MotionBlurScene : public testing::ScratchDir {
 protected:
  // Runs the falling jelly at `fps` with `shutter`, frames first..last; returns OUT.
  fs::path run(int fps, double shutter, int first, int last) {
    const fs::path scene = write("fall.toml", R"([simulation]
dt = 0.0025
duration = 0.7
fps = )" + std::to_string(fps) + R"(

[bodies.jelly]
type = "jelly"
n = 3
size = 0.5
center = [0, 2, 0]
color = [0.9, 0.6, 0.1]

[camera]
position = [0, 1, 4]
look_at = [0, 1, 0]
shutter = )" + std::to_string(shutter) + R"(
resolution = [48, 64]

[render]
samples = 16
noise_threshold = 0
denoise = false
)");
    const fs::path out = dir() / ("out_" + std::to_string(fps) + "_" + std::to_string(first));
    const int status = testing::runWobble("run " + scene.string() + " --frames " + std::to_string(first) + ":" +
                                              std::to_string(last) + " --render exr --out " + out.string(),
                                          dir() / "log.txt");
    EXPECT_EQ(status, 0) << testing::slurpFile(dir() / "log.txt");
    return out;
  }
  static image::ImageF frame(const fs::path& out, int k) {
    char name[32];
    std::snprintf(name, sizeof name, "exr/fall_%04d.exr", k);
    return image::readImageFile(out / name).image;
  }
  // The trapezoid average of frames first..last of a run.
  static image::ImageF average(const fs::path& out, int first, int last) {
    image::ImageF sum = frame(out, first);
    for (float& v : sum.pixels) v = 0;
    for (int k = first; k <= last; ++k) {
      const image::ImageF f = frame(out, k);
      const float w = (k == first || k == last ? 0.5f : 1.0f) / float(last - first);
      for (std::size_t i = 0; i < f.pixels.size(); ++i) sum.pixels[i] += w * f.pixels[i];
    }
    return sum;
  }
  static double rmse(const image::ImageF& a, const image::ImageF& b) {
    double s = 0;
    for (std::size_t i = 0; i < a.pixels.size(); ++i) s += std::pow(double(a.pixels[i]) - b.pixels[i], 2);
    return std::sqrt(s / double(a.pixels.size()));
  }
};

TEST_F(MotionBlurScene, ABlurredFrameIsTheAverageOfThePosesOverItsShutter) {
  // Frame 6 at 10 frames a second shows t = 0.5 s; a shutter of 1 opens at t = 0.4 s.
  const image::ImageF blurred = frame(run(10, 1.0, 6, 6), 6);
  // At 40 frames a second, frames 17 to 21 are t = 0.4 to 0.5 s (the shutter), 21 to 25 the interval after it.
  const fs::path stills = run(40, 0.0, 17, 25);
  const image::ImageF during = average(stills, 17, 21), after = average(stills, 21, 25);
  const image::ImageF closing = frame(stills, 21), half = average(stills, 19, 21);
  const double error = rmse(blurred, during);
  EXPECT_LT(error, 0.4 * rmse(blurred, closing)) << "the frame is not blurred";
  EXPECT_LT(error, 0.4 * rmse(blurred, after)) << "blurred after the frame's time, not before it";
  EXPECT_LT(error, 0.6 * rmse(blurred, half)) << "blurred over half the shutter";
  EXPECT_GT(rmse(closing, during), 0.02);  // the motion is large enough to tell these apart
}

}  // namespace
}  // namespace wobble
