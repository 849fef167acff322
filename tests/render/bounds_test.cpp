// Bounds: the slab test against rays that hit, miss, run parallel to a face or stop short.
#include "render/bounds.h"

#include <gtest/gtest.h>

namespace wobble::render {
namespace {

using Eigen::Vector3f;

TEST(Bounds, SlabTestAgreesWithTheBoxGeometry) {
  Bounds b;
  EXPECT_TRUE(b.isEmpty());
  EXPECT_FALSE(mayHit(b, Ray{{0, 0, 0}, {1, 0, 0}}));  // nothing to hit
  b.extend(Vector3f(1, 1, 1));
  b.extend(Vector3f(3, 2, 4));
  EXPECT_FALSE(b.isEmpty());
  EXPECT_TRUE(mayHit(b, Ray{{0, 1.5f, 2}, {1, 0, 0}}));                        // straight through, parallel to y and z
  EXPECT_FALSE(mayHit(b, Ray{{0, 2.5f, 2}, {1, 0, 0}}));                       // parallel, above the top face
  EXPECT_TRUE(mayHit(b, Ray{{0, 2.0f, 2}, {1, 0, 0}}));                        // along the top face
  EXPECT_FALSE(mayHit(b, Ray{{4, 1.5f, 2}, {1, 0, 0}}));                       // behind the origin
  EXPECT_TRUE(mayHit(b, Ray{{2, 1.5f, 2}, {0, 0, -1}}));                       // from inside
  EXPECT_FALSE(mayHit(b, Ray{{0, 1.5f, 2}, {1, 0, 0}, 0, 0.5f}));              // stops short
  EXPECT_FALSE(mayHit(b, Ray{{0, 0, 0}, Vector3f(1, 1.5f, 0).normalized()}));  // misses the corner in z
  EXPECT_TRUE(mayHit(b, Ray{{0, 0, 0}, Vector3f(2, 1.5f, 2.5f).normalized()}));
  const Bounds p = padded(b, 0.01f);  // by 1% of the largest coordinate, 4
  EXPECT_NEAR(p.min().x(), 0.96f, 1e-6f);
  EXPECT_NEAR(p.max().z(), 4.04f, 1e-6f);
  EXPECT_TRUE(mayHit(p, Ray{{0, 2.03f, 2}, {1, 0, 0}}));
}

}  // namespace
}  // namespace wobble::render
