// The integrator name table: every method is constructible by its name and reports it; unknown names are refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <string>

#include "sim/integrators/integrator.h"

namespace wobble {
namespace {

TEST(MethodTable, EveryNameMakesTheMethodOfThatName) {
  const auto names = integratorNames();
  for (const char* expected :
       {"explicit-euler", "symplectic-euler", "pc-euler", "midpoint", "rk4", "rk45", "backward-euler"})
    EXPECT_NE(std::find(names.begin(), names.end(), expected), names.end()) << expected;
  for (std::string_view name : names) EXPECT_EQ(makeIntegrator(name)->name(), name);
  try {
    makeIntegrator("implicit-euler");
    ADD_FAILURE() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("backward-euler"), std::string::npos) << e.what();
  }
}

TEST(MethodTable, EveryMethodStatesItsTraits) {
  for (std::string_view name : integratorNames()) EXPECT_GE(integratorTraits(name).order, 1) << name;
  EXPECT_EQ(integratorTraits("rk4").order, 4);
  EXPECT_TRUE(integratorTraits("rk45").adaptive);
  EXPECT_FALSE(integratorTraits("rk4").adaptive);
  EXPECT_TRUE(integratorTraits("backward-euler").a_stable);
  EXPECT_TRUE(integratorTraits("backward-euler").implicit);
  EXPECT_FALSE(integratorTraits("symplectic-euler").a_stable);
  EXPECT_THROW(integratorTraits("implicit-euler"), std::invalid_argument);
}

}  // namespace
}  // namespace wobble
