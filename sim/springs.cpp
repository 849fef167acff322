#include "sim/springs.h"

#include <algorithm>
#include <cmath>

namespace wobble {

std::string_view toString(SpringType type) {
  switch (type) {
    case SpringType::Structural:
      return "structural";
    case SpringType::Shear:
      return "shear";
    case SpringType::Bending:
      return "bending";
  }
  return "?";
}

void Springs::add(int pa, int pb, double rest_length, double stiffness, double damping, SpringType t) {
  a.push_back(pa);
  b.push_back(pb);
  rest.push_back(rest_length);
  ks.push_back(stiffness);
  kd.push_back(damping);
  type.push_back(t);
}

void Springs::append(const Springs& o, int offset) {
  for (std::size_t i = 0; i < o.size(); ++i)
    add(o.a[i] + offset, o.b[i] + offset, o.rest[i], o.ks[i], o.kd[i], o.type[i]);
}

Springs Springs::permuted(const std::vector<int>& order) const {
  Springs out;
  for (const int i : order) out.add(a[i], b[i], rest[i], ks[i], kd[i], type[i]);
  return out;
}

std::size_t Springs::count(SpringType t) const { return std::count(type.begin(), type.end(), t); }

void addSpringForces(const Springs& s, int begin, int end, const VecX& x, const VecX& v, VecX& f) {
  // Scalar, with indexed loads: the reference, and the loop for springs outside long runs. The system's force loop
  // takes runs of springs through spring_runs.h, whose contiguous loads vectorise; a loop over scattered
  // springs is bound by its indexed loads and stores, so gathering them into arrays first would not help.
  for (int i = begin; i < end; ++i) {
    const int a = s.a[i], b = s.b[i];
    const Vec3 d = particle(x, a) - particle(x, b);
    const double len = d.norm();
    if (len == 0.0) continue;  // coincident endpoints: no direction, no force
    const Vec3 dir = d / len;
    const double relative_speed = (particle(v, a) - particle(v, b)).dot(dir);
    const Vec3 fa = (-s.ks[i] * (len - s.rest[i]) - s.kd[i] * relative_speed) * dir;
    particle(f, a) += fa;
    particle(f, b) -= fa;
  }
}

void addSpringForces(const Springs& s, const VecX& x, const VecX& v, VecX& f) {
  addSpringForces(s, 0, static_cast<int>(s.size()), x, v, f);
}

double springEnergy(const Springs& s, const VecX& x) {
  double e = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double stretch = (particle(x, s.a[i]) - particle(x, s.b[i])).norm() - s.rest[i];
    e += 0.5 * s.ks[i] * stretch * stretch;
  }
  return e;
}

double maxStrain(const Springs& s, const VecX& x) {
  double worst = 0;
  for (std::size_t i = 0; i < s.size(); ++i) {
    const double len = (particle(x, s.a[i]) - particle(x, s.b[i])).norm();
    worst = std::max(worst, std::abs(len - s.rest[i]) / s.rest[i]);
  }
  return worst;
}

}  // namespace wobble
