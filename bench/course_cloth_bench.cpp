// The course cloth (25 x 25, ks 20000, kd 750, corners pinned, over a unit sphere, dt 1e-4, explicit Euler) stepped
// by wobble and by a stand-in for the course framework's own code: single precision, one thread, particles as
// structs (position, velocity, force), springs as structs, the sphere tested for every particle every step, as
// that framework's cloth variant does (docs/numerics.md, "The course framework's constants"). The framework's source
// is not part of this project: this is a plain reimplementation of what it computes, to compare step costs on the
// same machine.
// Run: build/course_cloth_bench
#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <vector>

#include "sim/bodies/cloth.h"
#include "sim/contact/colliders/sphere.h"
#include "sim/integrators/integrator.h"
#include "sim/system.h"

namespace wobble {
namespace {

constexpr double kDt = 1e-4;

Body courseCloth() {
  ClothParams p;
  p.pinned = clothPinSet("corners", p.nx, p.ny);
  return buildCloth("cloth", p);
}

void wobbleStep(benchmark::State& state) {
  MassSpringSystem system;
  system.addBody(courseCloth());
  system.addCollider(
      std::make_unique<SphereCollider>("sphere", ContactParams{0, 0.5, 0.01}, Vec3::Zero(), 1.0, Vec3::Zero()));
  system.setStepSize(kDt);
  auto integrator = makeIntegrator("explicit-euler");
  VecX x = system.initialPositions(), v = system.initialVelocities();
  double t = 0;
  for (auto _ : state) {
    integrator->step(system, t, kDt, x, v);
    t += kDt;
    system.resolveCollisions(t, x, v);
    benchmark::DoNotOptimize(x.data());
  }
  state.counters["steps/s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

// The stand-in for the course framework's float cloth.
struct Particle {
  Eigen::Vector3f x, v, f;
  float inv_mass;
};
struct Spring {
  int a, b;
  float ks, kd, rest;
};

void courseStep(benchmark::State& state) {
  const Body body = courseCloth();
  std::vector<Particle> ps;
  for (int i = 0; i < body.particleCount(); ++i)
    ps.push_back({particle(body.x, i).cast<float>(), Eigen::Vector3f::Zero(), Eigen::Vector3f::Zero(),
                  body.pinned[i] ? 0.0f : 1.0f / float(body.mass[i])});
  std::vector<Spring> springs;
  const Springs& s = body.springs;
  for (std::size_t i = 0; i < s.size(); ++i)
    springs.push_back({s.a[i], s.b[i], float(s.ks[i]), float(s.kd[i]), float(s.rest[i])});
  const float dt = float(kDt), eps = 0.01f, mu = 0.5f, drag = float(body.drag), radius = 1;
  const Eigen::Vector3f gravity(0, -9.8f, 0);
  for (auto _ : state) {
    for (Particle& p : ps) p.f = gravity - drag * p.v;  // mass 1
    for (const Spring& sp : springs) {
      Particle &a = ps[sp.a], &b = ps[sp.b];
      const Eigen::Vector3f d = a.x - b.x;
      const float len = d.norm();
      const Eigen::Vector3f dir = d / len;
      const Eigen::Vector3f fa = (-sp.ks * (len - sp.rest) - sp.kd * (a.v - b.v).dot(dir)) * dir;
      a.f += fa;
      b.f -= fa;
    }
    for (Particle& p : ps) {  // contact force and friction against the sphere, then explicit Euler
      const Eigen::Vector3f n = p.x.normalized();
      const float push = n.dot(p.f);
      if (std::abs(p.x.norm() - radius) < eps && push < 0) {
        const Eigen::Vector3f vt = p.v - n.dot(p.v) * n;
        p.f -= push * n;
        if (vt.norm() > 0) p.f += mu * push * vt.normalized();
      }
      p.x += dt * p.v;
      p.v += dt * p.inv_mass * p.f;
      const float dist = p.x.norm() - radius;  // restitution 0 and penetration correction
      if (dist < eps) {
        const float vn = n.dot(p.v);
        if (vn < 0) p.v -= vn * n;
        if (dist < 0) p.x -= dist * n;
      }
    }
    benchmark::DoNotOptimize(ps.data());
  }
  state.counters["steps/s"] = benchmark::Counter(double(state.iterations()), benchmark::Counter::kIsRate);
}

BENCHMARK(wobbleStep)->Unit(benchmark::kMicrosecond);
BENCHMARK(courseStep)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace wobble
