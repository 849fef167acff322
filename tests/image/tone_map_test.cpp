// The tone map (image/color.h) against values worked by hand: the ACES fit and Reinhard at chosen points, exposure
// as a factor of 2 a stop, clamping of negatives and highlights, and toSrgb8 (the one-pass image path) giving the
// same codes as apply() followed by linearToSrgb8 over a sweep.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "image/color.h"

namespace wobble::image {
namespace {

TEST(ToneMap, CurvesMatchValuesWorkedByHand) {
  ToneMap aces;  // x (2.51 x + 0.03) / (x (2.43 x + 0.59) + 0.14)
  EXPECT_EQ(aces.curveOf(0), 0.0f);
  EXPECT_NEAR(aces.curveOf(1), 2.54f / 3.16f, 1e-6f);              // 0.803797
  EXPECT_NEAR(aces.curveOf(0.18f), 0.086724f / 0.324932f, 1e-6f);  // 0.266899 (middle grey)
  EXPECT_NEAR(aces.curveOf(4), 40.28f / 41.38f, 1e-6f);            // 0.973417
  EXPECT_EQ(aces.curveOf(100), 1.0f);                              // saturates: clamped to 1
  ToneMap reinhard{.curve = ToneMap::Curve::Reinhard};
  EXPECT_NEAR(reinhard.curveOf(1), 0.5f, 1e-7f);
  EXPECT_NEAR(reinhard.curveOf(3), 0.75f, 1e-7f);
  ToneMap clamp{.curve = ToneMap::Curve::Clamp};
  EXPECT_EQ(clamp.curveOf(0.25f), 0.25f);
  EXPECT_EQ(clamp.curveOf(7), 1.0f);
}

TEST(ToneMap, ExposureIsAFactorOfTwoAStopAndNegativesAreBlack) {
  const ToneMap plus_one{.exposure = 1, .curve = ToneMap::Curve::Clamp};
  EXPECT_EQ(plus_one.apply(0.2f), 0.4f);
  const ToneMap minus_two{.exposure = -2, .curve = ToneMap::Curve::Reinhard};
  EXPECT_NEAR(minus_two.apply(4), 0.5f, 1e-7f);  // 4 / 4 = 1 -> 1 / 2
  EXPECT_EQ(ToneMap{}.apply(-3), 0.0f);
}

TEST(ToneMap, OnePassEncodingEqualsApplyThenEncode) {
  std::vector<float> values;
  for (int i = 0; i <= 4000; ++i) values.push_back(std::pow(10.0f, -4.0f + 6.0f * float(i) / 4000.0f));  // 1e-4..100
  values.push_back(-1.0f);
  values.push_back(0.0f);
  for (const ToneMap::Curve curve : {ToneMap::Curve::Aces, ToneMap::Curve::Reinhard, ToneMap::Curve::Clamp})
    for (const float exposure : {-1.5f, 0.0f, 2.0f}) {
      const ToneMap tm{.exposure = exposure, .curve = curve};
      std::vector<std::uint8_t> codes(values.size());
      tm.toSrgb8(values, codes.data());
      int different = 0;
      for (std::size_t i = 0; i < values.size(); ++i) different += codes[i] != linearToSrgb8(tm.apply(values[i]));
      EXPECT_EQ(different, 0) << "curve " << int(curve) << " exposure " << exposure;
      EXPECT_EQ(codes.back(), 0);                          // 0 is black
      EXPECT_LT(codes.front(), codes[values.size() - 3]);  // 1e-4 darker than 100
    }
}

}  // namespace
}  // namespace wobble::image
