// Direction sampling helpers: the polynomial (cos, sin) of 2 pi u against libm in double precision, and the cosine
// hemisphere's and the cone's samples against their own definitions.
#include "render/sampling.h"

#include <cmath>

#include <gtest/gtest.h>

namespace wobble::render {
namespace {

TEST(Sampling, CosSin2PiMatchesLibmToFloatPrecision) {
  double worst = 0;
  for (int i = -1000; i <= 1001000; ++i) {  // [0, 1] by 1e-6, a little beyond on both sides
    const float u = static_cast<float>(i) * 1e-6f;
    const Eigen::Vector2f cs = cosSin2Pi(u);
    const double phi = 2.0 * std::numbers::pi * static_cast<double>(u);
    worst = std::max({worst, std::abs(cs.x() - std::cos(phi)), std::abs(cs.y() - std::sin(phi))});
  }
  EXPECT_LT(worst, 3e-7);
  for (const float u : {0.0f, 0.25f, 0.5f, 0.75f}) {  // quarter turns are exact
    const double phi = 2.0 * std::numbers::pi * u;
    EXPECT_EQ(cosSin2Pi(u).x(), static_cast<float>(std::round(std::cos(phi))));
    EXPECT_EQ(cosSin2Pi(u).y(), static_cast<float>(std::round(std::sin(phi))));
  }
}

TEST(Sampling, HemisphereAndConeSamplesHaveTheirDefiningAngles) {
  for (const float u1 : {0.0f, 0.1f, 0.5f, 0.9f, 0.999f})
    for (const float u2 : {0.0f, 0.2f, 0.45f, 0.8f}) {
      const Eigen::Vector3f d = sampleCosineHemisphere(u1, u2);
      EXPECT_NEAR(d.norm(), 1.0f, 1e-6f);
      EXPECT_NEAR(d.z(), std::sqrt(1.0f - u1), 1e-6f);  // Malley: the disc point's radius is sqrt(u1)
      if (u1 > 0) {
        EXPECT_NEAR(std::atan2(d.y(), d.x()), std::remainder(2.0 * std::numbers::pi * u2, 2 * std::numbers::pi), 1e-5);
      }
      const Eigen::Vector3f c = sampleUniformCone(u1, u2, 0.9f);
      EXPECT_NEAR(c.norm(), 1.0f, 1e-6f);
      EXPECT_NEAR(c.z(), 1.0f - u1 * 0.1f, 1e-6f);
    }
}

}  // namespace
}  // namespace wobble::render
