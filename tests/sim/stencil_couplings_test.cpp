// The stencil couplings of the implicit solver's matrix (sim/solver/pair_block_matrix.h): contact between bodies
// inside backward Euler's solve adds W^T B W for each pressed pair's stencil W. Their product runs on threads in two
// passes (each stencil's u = B W x, then each particle gathers its w_i u in stencil order); checked against the dense
// matrix assembled here, and against the plain one-thread loop over stencils, byte for byte, in double and float.
#include <gtest/gtest.h>

#include <cstring>
#include <random>

#include "dense_matrix.h"
#include "sim/bodies/cloth.h"
#include "sim/solver/pair_block_matrix.h"
#include "sim/system.h"

namespace wobble {
namespace {

// The one-thread loop the threaded product must reproduce: stencil by stencil, u = B sum_j w_j x_j, y_i += w_i u
// (double).
void serialStencilProducts(const StencilCouplings& stencils, const double* x, double* y) {
  for (const StencilBlock& b : stencils) {
    const WeightedStencil& s = b.stencil;
    Vec3 d = Vec3::Zero();
    for (int j = 0; j < s.size; ++j)
      if (s.w[j] != 0) d += s.w[j] * Vec3(x[3 * s.particle[j]], x[3 * s.particle[j] + 1], x[3 * s.particle[j] + 2]);
    const Vec3 u = b.block * d;
    for (int i = 0; i < s.size; ++i)
      if (s.w[i] != 0)
        for (int k = 0; k < 3; ++k) y[3 * s.particle[i] + k] += s.w[i] * u[k];
  }
}

// The float product's arithmetic (the CG's inner iterations): float weights and blocks, float sums, stencil by
// stencil.
void serialStencilProducts(const StencilCouplings& stencils, const float* x, float* y) {
  for (const StencilBlock& b : stencils) {
    const WeightedStencil& s = b.stencil;
    float d[3] = {0, 0, 0};
    for (int j = 0; j < s.size; ++j)
      if (s.w[j] != 0)
        for (int k = 0; k < 3; ++k) d[k] += float(s.w[j]) * x[3 * s.particle[j] + k];
    const float xx = float(b.block.xx), yy = float(b.block.yy), zz = float(b.block.zz), xy = float(b.block.xy),
                xz = float(b.block.xz), yz = float(b.block.yz);
    const float u[3] = {xx * d[0] + xy * d[1] + xz * d[2], xy * d[0] + yy * d[1] + yz * d[2],
                        xz * d[0] + yz * d[1] + zz * d[2]};
    for (int i = 0; i < s.size; ++i)
      if (s.w[i] != 0)
        for (int k = 0; k < 3; ++k) y[3 * s.particle[i] + k] += float(s.w[i]) * u[k];
  }
}

TEST(StencilCouplings, ThreadedProductEqualsTheDenseMatrixAndTheOneThreadLoopByteForByte) {
  ClothParams p;
  p.nx = p.ny = 40;
  MassSpringSystem system;
  system.addBody(buildCloth("cloth", p));
  const int n = system.particleCount();
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0, 0.01);
  std::uniform_int_distribution<int> pick(0, n - 1), size(2, 12);
  VecX x = system.initialPositions(), v = VecX::Zero(x.size()), y(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) x[i] += noise(rng), y[i] = noise(rng);

  PairBlockMatrix a;
  a.reset(system.jacobianPattern());
  system.fillJacobian(0, x, v, 1e-4, 1e-2, a, nullptr, nullptr);
  for (double& s : a.self()) s += 0.01;
  // 3000 stencils of 2 to 12 distinct particles (about 13 stencils a particle), a few weights 0: enough stencils and
  // particles for both passes to run in several chunks on threads.
  for (int k = 0; k < 3000; ++k) {
    StencilBlock b;
    const int m = size(rng);
    while (b.stencil.size < m) {
      const int q = pick(rng);
      bool in = false;
      for (int i = 0; i < b.stencil.size; ++i) in |= b.stencil.particle[i] == q;
      if (!in) b.stencil.add(q, k % 7 == 0 && b.stencil.size == 1 ? 0.0 : noise(rng) * 100);
    }
    const Vec3 normal = Vec3(noise(rng), noise(rng), noise(rng)).normalized();
    b.block = 1e3 * Sym3::outer(normal) + Sym3::identity(10);
    a.stencils().push_back(b);
  }

  const Eigen::MatrixXd dense = testing::denseMatrix(a);  // the pattern's blocks and each stencil's w_i w_j B

  VecX threaded, one_thread;
  a.multiply(y, threaded, true);
  a.multiply(y, one_thread, false);
  const VecX expected = dense * y;
  EXPECT_LE((threaded - expected).cwiseAbs().maxCoeff(), 1e-10 * expected.cwiseAbs().maxCoeff());
  EXPECT_EQ(0, std::memcmp(threaded.data(), one_thread.data(), sizeof(double) * threaded.size()));

  // Against the plain loop over stencils, after the pattern's part: the same bytes, in double and in float.
  VecX reference(x.size());
  multiplyFused(a, y.data(), reference.data(), false, [](int, int) {});  // pattern and stencils ...
  EXPECT_EQ(0, std::memcmp(threaded.data(), reference.data(), sizeof(double) * threaded.size()));
  StencilCouplings saved = a.stencils();
  a.stencils().clear();
  multiplyFused(a, y.data(), reference.data(), false, [](int, int) {});  // ... the pattern alone
  serialStencilProducts(saved, y.data(), reference.data());
  EXPECT_EQ(0, std::memcmp(threaded.data(), reference.data(), sizeof(double) * threaded.size()));
  a.stencils() = saved;

  SinglePairBlockMatrix single;
  single.assign(a, false);
  std::vector<float> ys(y.size()), threaded_f(y.size()), serial_f(y.size());
  for (Eigen::Index i = 0; i < y.size(); ++i) ys[i] = float(y[i]);
  multiplyFused(single, ys.data(), threaded_f.data(), true, [](int, int) {});
  a.stencils().clear();  // single reads a's stencils: the pattern's part alone, then the loop
  multiplyFused(single, ys.data(), serial_f.data(), false, [](int, int) {});
  serialStencilProducts(saved, ys.data(), serial_f.data());
  EXPECT_EQ(0, std::memcmp(threaded_f.data(), serial_f.data(), sizeof(float) * serial_f.size()));
}

}  // namespace
}  // namespace wobble
