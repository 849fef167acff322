// A gelatine body's absorption keys (scenes/README.md: absorption_color, the colour white light takes after
// absorption_depth metres inside) as the medium's coefficients the renderer traces (render/material.h: sigma_a per
// channel). Oracle: Beer-Lambert, exp(-sigma_a d) is the colour at depth d, and at any other depth its power d / depth.
#include <gtest/gtest.h>

#include <cmath>

#include "app/scene/material_kinds.h"
#include "app/scene/scene_file.h"
#include "tests/app/scratch_dir.h"

namespace wobble {
namespace {

class GelatineLook : public testing::ScratchDir {
 protected:
  render::Material material(const std::string& color, double depth) {
    const SceneFile scene = loadScene(write("gel.toml", R"([bodies.jelly]
type = "jelly"
n = 3
center = [0, 1, 0]
material = "gelatine"
absorption_color = )" + color + "\nabsorption_depth = " + std::to_string(depth) +
                                                            "\n"));
    const BodyLook& look = scene.render.bodies.at("jelly");
    return materialKind(look.material).make("jelly", look, nullptr);
  }
};

TEST_F(GelatineLook, AbsorptionColourAndDepthAreTheMediumsCoefficients) {
  const double depth = 0.25;
  const double color[3] = {0.8, 0.3, 0.05};
  const render::Material m = material("[0.8, 0.3, 0.05]", depth);
  for (int c = 0; c < 3; ++c) {
    // Beer-Lambert: white light keeps `color` after `depth` metres, and color^(d / depth) after d.
    EXPECT_NEAR(std::exp(-m.absorption[c] * depth), color[c], 1e-5 * color[c]) << "channel " << c;
    EXPECT_NEAR(std::exp(-m.absorption[c] * 2 * depth), color[c] * color[c], 1e-5 * color[c]) << "channel " << c;
    EXPECT_NEAR(m.absorption[c], -std::log(color[c]) / depth, 1e-4 * m.absorption[c]) << "channel " << c;
  }
}

TEST_F(GelatineLook, AColourOfOneAbsorbsNothingAndADeeperDepthAbsorbsLess) {
  const render::Material clear = material("[1, 1, 1]", 1);
  EXPECT_EQ(clear.absorption, render::Color::Zero());
  const render::Material shallow = material("[0.5, 0.5, 0.5]", 0.1), deep = material("[0.5, 0.5, 0.5]", 2);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(shallow.absorption[c], 20 * deep.absorption[c], 1e-4 * shallow.absorption[c]);
}

}  // namespace
}  // namespace wobble
