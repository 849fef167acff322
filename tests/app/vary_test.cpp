// --vary parsing (app/compare/vary.h): values split at top-level commas (a TOML array or a quoted string stays one
// value), what each value sets, and the input errors, each naming the flag.
#include <gtest/gtest.h>

#include "app/compare/vary.h"
#include "app/scene/input_error.h"

namespace wobble {
namespace {

std::string errorOf(const std::string& text) {
  try {
    parseVary(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(Vary, SplitsValuesAtTopLevelCommas) {
  const VaryAxis a = parseVary("integrator=explicit-euler,pc-euler,midpoint,rk4");
  EXPECT_EQ(a.key, "integrator");
  EXPECT_EQ(a.values, (std::vector<std::string>{"explicit-euler", "pc-euler", "midpoint", "rk4"}));
  const VaryAxis b = parseVary("camera.position=[0,5,9],[0, 9, 5]");
  EXPECT_EQ(b.values, (std::vector<std::string>{"[0,5,9]", "[0, 9, 5]"}));
  EXPECT_EQ(parseVary("jelly.texture=\"a,b.png\",'c.png'").values,
            (std::vector<std::string>{"\"a,b.png\"", "'c.png'"}));
  EXPECT_EQ(parseVary("jelly.ks=5e4").values.size(), 1u);
  EXPECT_EQ(varyFlag(b), "--vary camera.position=[0,5,9],[0, 9, 5]");
}

TEST(Vary, WhatEachValueSets) {
  const VariedSetting i = variedSetting(parseVary("integrator=rk4,midpoint"), "midpoint");
  EXPECT_EQ(i.integrator, "midpoint");
  EXPECT_FALSE(i.dt || i.set);
  const VariedSetting d = variedSetting(parseVary("dt=1.2e-3,1e-3"), "1.2e-3");
  EXPECT_EQ(d.dt, 1.2e-3);
  EXPECT_FALSE(d.integrator || d.set);
  const VariedSetting s = variedSetting(parseVary("jelly.ks=5e4,1e5"), "1e5");
  EXPECT_EQ(s.set, "jelly.ks=1e5");
  EXPECT_THROW(variedSetting(parseVary("dt=fast,1e-3"), "fast"), InputError);
  EXPECT_THROW(variedSetting(parseVary("dt=1e-3x,1e-3"), "1e-3x"), InputError);
  try {
    variedSetting(parseVary("dt=fast,1e-3"), "fast");
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--vary dt=fast,1e-3: dt 'fast' is not a number"), std::string::npos)
        << e.what();
  }
}

TEST(Vary, BadInputNamesTheFlag) {
  EXPECT_NE(errorOf("integrator").find("--vary integrator: no '='"), std::string::npos) << errorOf("integrator");
  EXPECT_NE(errorOf("=rk4").find("no key"), std::string::npos);
  EXPECT_NE(errorOf("jelly.ks=").find("--vary jelly.ks=: an empty list of values"), std::string::npos);
  EXPECT_NE(errorOf("jelly.ks=1e4,,5e4").find("value 2 is empty"), std::string::npos);
  EXPECT_NE(errorOf("jelly.ks=1e4,").find("value 2 is empty"), std::string::npos);
  EXPECT_NE(errorOf("integrator=rk4,rk4").find("the value rk4 is given twice"), std::string::npos);
  EXPECT_NE(errorOf("jelly.ks=").find("expected KEY=V1,V2,..."), std::string::npos);
}

}  // namespace
}  // namespace wobble
