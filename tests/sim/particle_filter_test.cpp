// Baraff & Witkin's filter with several constraints on one particle (1998, section 5.3; particle_filter.h) and the
// velocity change the contacts prescribe (contact/constraints/filter.h). Oracles: the algebra of an orthogonal
// projection (symmetric, idempotent, zero on every constraint normal, identity on the free directions) and the
// constraints themselves (n_i . z = h a_i for each).
#include <gtest/gtest.h>

#include "sim/contact/constraints/filter.h"

namespace wobble {
namespace {

const Vec3 kN1 = Vec3(0.3, 1, -0.2).normalized();
const Vec3 kN2 = Vec3(-0.8, 0.5, 0.1).normalized();
const Vec3 kN3 = Vec3(0.1, 0.2, 1).normalized();

ParticleFilter filterOf(int n) {
  ParticleFilter s;
  s.reset(VecX::Ones(n));
  return s;
}

// S_p is an orthogonal projection that removes every normal and keeps `free` (a basis of what is left) whole.
void expectProjection(const ParticleFilter& s, int p, const std::vector<Vec3>& normals, const std::vector<Vec3>& free) {
  const Eigen::Matrix3d m = s.matrix(p);
  EXPECT_LT((m - m.transpose()).norm(), 1e-15) << "symmetric";
  EXPECT_LT((m * m - m).norm(), 1e-15) << "idempotent";
  EXPECT_NEAR(m.trace(), double(free.size()), 1e-15) << "rank";
  for (const Vec3& n : normals) EXPECT_LT((m * n).norm(), 1e-15) << "S n = 0 for n = " << n.transpose();
  for (const Vec3& d : free) EXPECT_LT((m * d - d).norm(), 1e-15) << "S d = d for d = " << d.transpose();
  for (const Vec3& y : {Vec3(1, 2, 3), Vec3(-0.4, 0.1, 7)}) {
    EXPECT_LT((s.apply(p, y) - m * y).norm(), 1e-14) << "apply agrees with the matrix";
    EXPECT_LT((s.removed(p, y) - (y - m * y)).norm(), 1e-14);
  }
}

TEST(ParticleFilter, OneNormalLeavesItsPlane) {
  ParticleFilter s = filterOf(2);
  EXPECT_FALSE(s.anyConstrained());
  s.constrain(1, kN1);
  EXPECT_EQ(s.kind(0), ParticleFilter::Free);
  EXPECT_EQ(s.kind(1), ParticleFilter::Normal);
  EXPECT_TRUE(s.anyConstrained());
  const Vec3 t1 = kN1.unitOrthogonal();
  expectProjection(s, 1, {kN1}, {t1, kN1.cross(t1)});
  expectProjection(s, 0, {}, {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()});
}

TEST(ParticleFilter, TwoNormalsLeaveTheirLineOfIntersection) {
  ParticleFilter s = filterOf(1);
  s.constrain(0, kN1);
  s.constrain(0, kN2);
  ASSERT_EQ(s.kind(0), ParticleFilter::Line);
  const Vec3 d = kN1.cross(kN2).normalized();
  EXPECT_NEAR(std::abs(s.direction(0).dot(d)), 1, 1e-15);
  expectProjection(s, 0, {kN1, kN2}, {d});
  // The order of the two does not matter.
  ParticleFilter r = filterOf(1);
  r.constrain(0, kN2);
  r.constrain(0, kN1);
  EXPECT_LT((r.matrix(0) - s.matrix(0)).norm(), 1e-15);
}

TEST(ParticleFilter, ThreeIndependentNormalsHoldTheParticle) {
  ParticleFilter s = filterOf(1);
  for (const Vec3& n : {kN1, kN2, kN3}) s.constrain(0, n);
  EXPECT_EQ(s.kind(0), ParticleFilter::Held);
  expectProjection(s, 0, {kN1, kN2, kN3}, {});
  EXPECT_EQ(s.apply(0, Vec3(1, 2, 3)), Vec3::Zero());
  s.constrain(0, kN1);  // more normals: still held
  EXPECT_EQ(s.kind(0), ParticleFilter::Held);
}

TEST(ParticleFilter, NearlyParallelNormalsCountAsOne) {
  // A second normal within kParallel of the first: one constraint (a line from them would be ill-conditioned).
  ParticleFilter s = filterOf(1);
  const Vec3 tilted = (kN1 + 0.5 * ParticleFilter::kParallel * kN1.unitOrthogonal()).normalized();
  s.constrain(0, kN1);
  s.constrain(0, tilted);
  EXPECT_EQ(s.kind(0), ParticleFilter::Normal);
  EXPECT_EQ(s.normal(0), kN1);
  s.constrain(0, kN1);  // the same surface twice: the same constraint
  EXPECT_EQ(s.kind(0), ParticleFilter::Normal);
  // A third normal in the plane of two: still their line.
  ParticleFilter line = filterOf(1);
  line.constrain(0, kN1);
  line.constrain(0, kN2);
  line.constrain(0, (kN1 + 2 * kN2).normalized());
  EXPECT_EQ(line.kind(0), ParticleFilter::Line);
  expectProjection(line, 0, {kN1, kN2}, {kN1.cross(kN2).normalized()});
}

TEST(ParticleFilter, APinnedParticleStaysHeld) {
  ParticleFilter s;
  s.reset(VecX::Zero(1));
  s.constrain(0, kN1);
  EXPECT_EQ(s.kind(0), ParticleFilter::Held);
}

// The prescribed velocity change z of a particle on one, two or three surfaces: in the removed directions, and every
// constraint's normal component at once. A particle with one keeps exactly h a n (the single-contact path).
TEST(ContactFilter, PrescribedChangeMeetsEveryNormalAtOnce) {
  const double h = 0.02;
  const std::vector<ContactConstraint> constraints = {
      {1, kN1, 3.0, 0},                                        // one surface
      {2, kN1, -1.5, 0}, {2, kN2, 2.0, 1},                     // a wedge
      {4, kN1, 0.5, 0},  {4, kN2, -2.5, 1}, {4, kN3, 4.0, 2},  // a corner
  };
  ParticleFilter s = filterOf(5);
  constrainFilter(constraints, s);
  EXPECT_EQ(s.kind(1), ParticleFilter::Normal);
  EXPECT_EQ(s.kind(2), ParticleFilter::Line);
  EXPECT_EQ(s.kind(4), ParticleFilter::Held);
  VecX dv = VecX::Zero(15);
  addPrescribedChange(constraints, s, h, dv);
  EXPECT_EQ(particle(dv, 1), Vec3(h * 3.0 * kN1));
  for (const ContactConstraint& c : constraints) {
    EXPECT_NEAR(c.normal.dot(particle(dv, c.particle)), h * c.normal_acceleration, 1e-15) << c.particle;
    EXPECT_LT(s.apply(c.particle, particle(dv, c.particle)).norm(), 1e-15) << "z is in what S removes";
  }
  for (const int free : {0, 3}) EXPECT_EQ(particle(dv, free), Vec3::Zero());
}

}  // namespace
}  // namespace wobble
