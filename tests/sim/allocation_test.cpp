// No integrator allocates memory in a step once its buffers are sized (after the first steps). Counted by
// interposing malloc for this test program (Eigen and operator new both end there); not under AddressSanitizer,
// which owns malloc itself.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>

#include "sim/simulation.h"
#include "tests/sim/cloth_on_sphere.h"

#if defined(__SANITIZE_ADDRESS__)
#define WOBBLE_COUNTS_MALLOC 0
#else
#define WOBBLE_COUNTS_MALLOC 1
namespace {
std::atomic<long> mallocs{0};
}
extern "C" void* __libc_malloc(std::size_t size);
extern "C" void* malloc(std::size_t size) {
  mallocs.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(size);
}
#endif

namespace wobble {
namespace {

TEST(Allocation, NoIntegratorAllocatesPerStep) {
  if (!WOBBLE_COUNTS_MALLOC) GTEST_SKIP() << "malloc is AddressSanitizer's here";
  const auto system = testing::clothOnSphere(12);
  for (std::string_view name : integratorNames()) {
    const double dt = name == "backward-euler" ? 1.0 / 240 : 1e-4;
    Simulation sim(*system, makeIntegrator(name), dt);
    ASSERT_FALSE(sim.advanceTo(3 * dt));  // sizes every buffer
    const long before = mallocs.load();
    ASSERT_FALSE(sim.advanceTo(20 * dt));
    EXPECT_EQ(mallocs.load() - before, 0) << name;
  }
  EXPECT_GT(mallocs.load(), 0);  // the counter counts: building the system allocated
}

}  // namespace
}  // namespace wobble
