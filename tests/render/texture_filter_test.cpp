// Texture filtering: evalFootprint is a point lookup for a zero footprint and, for checker and wood, the box average of
// the texture over the footprint's bounding box (checked against brute-force averages); huge footprints settle down.
#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <vector>

#include <gtest/gtest.h>

#include "render/image_texture.h"
#include "render/texture.h"

namespace wobble::render {
namespace {

using Eigen::Vector2f;

TextureFootprint footprint(const Vector2f& duvdx, const Vector2f& duvdy, const Vector2f& jitter = {0.5f, 0.5f}) {
  TextureFootprint f;
  f.duvdx = duvdx, f.duvdy = duvdy, f.jitter = jitter;
  return f;
}

// Brute force: the mean of eval over an nu x nv grid of cell midpoints of the footprint's bounding box,
// uv +- (|duvdx| + |duvdy|) / 2 per axis.
Color boxAverage(const Texture& t, const Vector2f& uv, const TextureFootprint& f, int nu, int nv) {
  const Eigen::Vector2d half = 0.5 * (f.duvdx.cwiseAbs() + f.duvdy.cwiseAbs()).cast<double>();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double u = uv.x() - half.x() + 2 * half.x() * (i + 0.5) / nu;
      const double v = uv.y() - half.y() + 2 * half.y() * (j + 0.5) / nv;
      sum += t.eval(Vector2f(float(u), float(v))).cast<double>();
    }
  return (sum / double(nu * nv)).cast<float>();
}

// Exact for the checker, whose colour is constant on squares [i, i + 1) x [j, j + 1) / squares: the bounding box cut
// along the square edges inside it into rectangles, each weighted by its area and valued by eval at its centre.
Color checkerBoxAverage(const CheckerTexture& t, float squares, const Vector2f& uv, const TextureFootprint& f) {
  const Eigen::Vector2d half = 0.5 * (f.duvdx.cwiseAbs() + f.duvdy.cwiseAbs()).cast<double>();
  const auto cuts = [&](double centre, double h) {
    std::vector<double> c{centre - h};
    for (double k = std::floor((centre - h) * squares) + 1; k / squares < centre + h; ++k) c.push_back(k / squares);
    c.push_back(centre + h);
    return c;
  };
  const std::vector<double> us = cuts(uv.x(), half.x()), vs = cuts(uv.y(), half.y());
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j + 1 < vs.size(); ++j)
    for (std::size_t i = 0; i + 1 < us.size(); ++i) {
      const Vector2f centre(float(0.5 * (us[i] + us[i + 1])), float(0.5 * (vs[j] + vs[j + 1])));
      sum += (us[i + 1] - us[i]) * (vs[j + 1] - vs[j]) * t.eval(centre).cast<double>();
    }
  return (sum / (4 * half.x() * half.y())).cast<float>();
}

float maxChannelDifference(const Color& a, const Color& b) { return (a - b).cwiseAbs().maxCoeff(); }

const std::vector<Vector2f> kCentres{{0.137f, 0.291f}, {0.5f, 0.5f}, {0.731f, 0.06f}, {2.31f, -1.17f}, {-0.42f, 3.9f}};

// Footprints of one size in several orientations: axis-aligned, rotated, sheared (a grazing view).
std::vector<TextureFootprint> footprints(float size) {
  std::vector<TextureFootprint> all;
  for (const float angle : {0.0f, 0.4f, 1.1f}) {
    const Vector2f a(std::cos(angle), std::sin(angle)), b(-std::sin(angle), std::cos(angle));
    all.push_back(footprint(size * a, size * b));                            // a square
    all.push_back(footprint(size * a, 0.25f * size * b + 0.5f * size * a));  // a sheared, flattened one
  }
  return all;
}

TEST(TextureFilter, ZeroFootprintIsAPointLookup) {
  const CheckerTexture checker(Color(0.9f, 0.1f, 0.2f), Color(0.1f, 0.8f, 0.3f), 8);
  const WoodTexture wood;
  std::vector<Color> texels;
  for (int i = 0; i < 16; ++i) texels.emplace_back(i / 16.0f, (i * 7 % 16) / 16.0f, 0.5f);
  const ImageTexture image(4, 4, texels);
  const TextureFootprint zero;  // duvdx = duvdy = 0
  for (const Texture* t : std::initializer_list<const Texture*>{&checker, &wood, &image})
    for (const Vector2f& uv : kCentres) {
      EXPECT_EQ(t->evalFootprint(uv, zero), t->eval(uv)) << uv.transpose();
      // Whatever the jitter.
      EXPECT_EQ(t->evalFootprint(uv, footprint(Vector2f::Zero(), Vector2f::Zero(), {0.1f, 0.9f})), t->eval(uv));
    }
}

TEST(TextureFilter, CheckerIsTheBoxAverageOverTheBoundingBox) {
  const CheckerTexture checker(Color(0.9f, 0.1f, 0.2f), Color(0.1f, 0.8f, 0.3f), 8);
  int differs_from_point = 0;
  for (const float size : {0.004f, 0.02f, 0.07f, 0.2f, 1.3f})
    for (const TextureFootprint& f : footprints(size))
      for (const Vector2f& uv : kCentres) {
        const Color filtered = checker.evalFootprint(uv, f);
        EXPECT_LT(maxChannelDifference(filtered, checkerBoxAverage(checker, 8, uv, f)), 1e-3f)
            << "uv " << uv.transpose() << " duvdx " << f.duvdx.transpose() << " duvdy " << f.duvdy.transpose();
        differs_from_point += maxChannelDifference(filtered, checker.eval(uv)) > 0.05f;
      }
  EXPECT_GT(differs_from_point, 20);  // the footprints do straddle square edges
}

// WoodTexture's closed-form filter against the box average over the footprint's bounding box: each board the box spans
// over its own part, the late-wood band by the exact box average of frac^5, the waves damped by their sincs.
TEST(TextureFilter, WoodIsCloseToTheBoxAverageOverTheBoundingBox) {
  const WoodTexture wood;
  int differs_from_point = 0;
  for (const float size : {0.001f, 0.004f, 0.02f, 0.07f, 0.2f}) {
    float worst = 0;
    Vector2f worst_uv = Vector2f::Zero();
    for (const TextureFootprint& f : footprints(size))
      for (const Vector2f& uv : kCentres) {
        const Color filtered = wood.evalFootprint(uv, f);
        const float e = maxChannelDifference(filtered, boxAverage(wood, uv, f, 128, 128));
        if (e > worst) worst = e, worst_uv = uv;
        differs_from_point += maxChannelDifference(filtered, wood.eval(uv)) > 0.03f;
      }
    // The grain filter is approximate (sinc-damped waves, per-board tones fading to their mean): 0.03 per channel.
    EXPECT_LT(worst, 0.03f) << "footprint size " << size << ", worst at uv " << worst_uv.transpose();
  }
  EXPECT_GT(differs_from_point, 10);  // the footprints do cover grain and joints
}

// What the wood filter does achieve: over many centres its RMS error against the box average stays within 0.03 and
// under that of a point lookup (no filtering at all), for footprints from a few grain lines to most of a board.
TEST(TextureFilter, WoodFilterBeatsPointLookupOnAverage) {
  const WoodTexture wood;
  for (const float size : {0.004f, 0.02f, 0.2f}) {
    double filtered_sq = 0, point_sq = 0;
    int n = 0;
    for (int k = 0; k < 64; ++k) {
      // Centres spread over many boards and along them (a Kronecker sequence).
      const Vector2f uv(std::fmod(0.7548777f * k, 1.0f) * 6 - 3, std::fmod(0.5698403f * k, 1.0f) * 4);
      const TextureFootprint f = footprint({size, 0.3f * size}, {-0.2f * size, size});
      const Color box = boxAverage(wood, uv, f, 128, 128);
      filtered_sq += std::pow(maxChannelDifference(wood.evalFootprint(uv, f), box), 2.0f);
      point_sq += std::pow(maxChannelDifference(wood.eval(uv), box), 2.0f);
      ++n;
    }
    const double filtered = std::sqrt(filtered_sq / n), point = std::sqrt(point_sq / n);
    EXPECT_LT(filtered, 0.03) << "footprint size " << size;
    EXPECT_LT(filtered, point) << "footprint size " << size;
  }
}

TEST(TextureFilter, HugeFootprintOverCheckerGivesTheMeanOfItsColours) {
  const Color a(0.9f, 0.1f, 0.2f), b(0.1f, 0.8f, 0.3f);
  const CheckerTexture checker(a, b, 8);
  for (const Vector2f& uv : kCentres)
    for (const TextureFootprint& f :
         {footprint({100, 0}, {0, 100}), footprint({70, 70}, {-70, 70}), footprint({300, 20}, {5, 150})}) {
      // Over 800 squares or more the box holds at most one square's worth of imbalance per axis: 1/800 of it.
      EXPECT_LT(maxChannelDifference(checker.evalFootprint(uv, f), 0.5f * (a + b)), 2e-3f) << uv.transpose();
    }
}

// The far floor: footprints spanning many boards. Values stay between the joint colour and the palest tone, follow the
// box average (the boards' tones do not average out over eight boards, so the box average itself moves by a few
// percent), and do not sparkle: moving the centre by 1% of the footprint moves the value by well under 1%.
TEST(TextureFilter, HugeFootprintOverWoodIsSteady) {
  const WoodTexture wood;  // light (0.60, 0.38, 0.20), dark (0.28, 0.14, 0.06)
  const Color light(0.60f, 0.38f, 0.20f), joint = 0.35f * Color(0.28f, 0.14f, 0.06f);
  const Color lightest = 1.12f * light;  // the palest board tone
  Color sum = Color::Zero();
  int n = 0;
  for (int j = 0; j < 10; ++j)
    for (int i = 0; i < 10; ++i) {
      const Vector2f uv(0.37f * i - 1.3f, 0.213f * j + 0.05f);
      for (const TextureFootprint& f : {footprint({3, 0}, {0, 2}), footprint({1.5f, 1.5f}, {-2, 2})}) {
        const Color c = wood.evalFootprint(uv, f);
        for (int k = 0; k < 3; ++k) {
          EXPECT_GE(c[k], joint[k]) << uv.transpose();
          EXPECT_LE(c[k], lightest[k]) << uv.transpose();
        }
        const Color nudged = wood.evalFootprint(uv + 0.01f * f.duvdx + 0.01f * f.duvdy, f);
        EXPECT_LT(maxChannelDifference(nudged, c), 0.01f * c.maxCoeff()) << uv.transpose() << ": sparkles";
        if ((i + j) % 5 == 0) {  // a subset against the brute-force box average (the fibre needs dense lookups)
          EXPECT_LT(maxChannelDifference(c, boxAverage(wood, uv, f, 64, 4096)), 0.03f) << uv.transpose();
        }
        sum += c, ++n;
      }
    }
  // On average the floor's mean colour: the brute-force mean over 64 boards (lookups 1/6 of the fibre's period apart
  // across them).
  const Color brute = boxAverage(wood, {0.5f, 8.0f}, footprint({0.5f, 0}, {0, 16}), 64, 16384);
  EXPECT_LT(maxChannelDifference(sum / float(n), brute), 0.03f);
}

// An image texture has no closed form: the grid of lookups. Over exactly one period of a 2 x 2 repeating image the
// grid (2 x 2 lookups half a period apart) meets each texel with total bilinear weight 1/4, so the result is the
// texels' mean whatever the centre and jitter.
TEST(TextureFilter, ImageTextureOverOnePeriodGivesTheMeanTexel) {
  const std::vector<Color> texels{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  const ImageTexture image(2, 2, texels, Wrap::Repeat);
  const Color mean = (texels[0] + texels[1] + texels[2] + texels[3]) / 4;
  for (const Vector2f& uv : kCentres)
    for (const Vector2f& jitter : {Vector2f(0.5f, 0.5f), Vector2f(0.1f, 0.8f), Vector2f(0.95f, 0.0f)}) {
      EXPECT_LT(maxChannelDifference(image.evalFootprint(uv, footprint({1, 0}, {0, 1}, jitter)), mean), 1e-5f)
          << uv.transpose();
      EXPECT_LT(maxChannelDifference(image.evalFootprint(uv, footprint({0, -1}, {1, 0}, jitter)), mean), 1e-5f)
          << uv.transpose();
    }
  // A footprint well under a texel is a point lookup.
  const Vector2f uv(0.3f, 0.6f);
  EXPECT_EQ(image.evalFootprint(uv, footprint({0.01f, 0}, {0, 0.01f})), image.eval(uv));
}

}  // namespace
}  // namespace wobble::render
