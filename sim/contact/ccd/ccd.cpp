#include "sim/contact/ccd/ccd.h"

#include <algorithm>
#include <cmath>

namespace wobble::collision {
namespace {

double evaluate(const std::array<double, 4>& c, double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }

// Roots of a t^2 + b t + c in (0, 1), by the cancellation-free formula; a linear or constant equation when a or b
// vanish relative to the others.
void quadraticRoots(double a, double b, double c, std::vector<double>& out) {
  const double scale = std::max({std::abs(a), std::abs(b), std::abs(c)});
  if (scale == 0) return;
  const auto keep = [&](double t) {
    if (t > 0 && t < 1) out.push_back(t);
  };
  if (std::abs(a) <= 1e-14 * scale) {
    if (std::abs(b) > 1e-14 * scale) keep(-c / b);
    return;
  }
  const double disc = b * b - 4 * a * c;
  if (disc < 0) {
    keep(-b / (2 * a));  // no real root: the nearest approach of f' to zero is still an extremum candidate of f
    return;
  }
  const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
  keep(q / a);
  if (q != 0) keep(c / q);
}

// A root of f in [lo, hi] where f(lo) and f(hi) have opposite signs, by bisection to the last bit.
double bisect(const std::array<double, 4>& c, double lo, double hi, double flo) {
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    const double fm = evaluate(c, mid);
    if (fm == 0) return mid;
    if ((fm < 0) == (flo < 0)) {
      lo = mid;
      flo = fm;
    } else {
      hi = mid;
    }
  }
  return 0.5 * (lo + hi);
}

// For four points coplanar over the whole step: the times in (0, 1) at which a point of one element crosses the line
// of an edge of the other, within their common plane.
void addInPlaneTimes(Primitive kind, const std::array<Vec3, 4>& x0, const std::array<Vec3, 4>& d,
                     std::vector<double>& times) {
  const auto at = [&](int i, double t) { return Vec3(x0[i] + t * d[i]); };
  Vec3 normal = Vec3::Zero();  // the plane's: the largest cross product of the points at the start or halfway
  for (const double t : {0.0, 0.5})
    for (int i = 1; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const Vec3 c = (at(i, t) - at(0, t)).cross(at(j, t) - at(0, t));
        if (c.squaredNorm() > normal.squaredNorm()) normal = c;
      }
  if (normal.squaredNorm() == 0) normal = Vec3::UnitZ();  // collinear points: any plane through them
  // (point, edge) pairs: a point-triangle's point against the three edges; each edge's ends against the other edge.
  static constexpr int kTriangle[3][3] = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}};
  static constexpr int kEdges[4][3] = {{0, 2, 3}, {1, 2, 3}, {2, 0, 1}, {3, 0, 1}};
  const int count = kind == Primitive::PointTriangle ? 3 : 4;
  for (int k = 0; k < count; ++k) {
    const int* s = kind == Primitive::PointTriangle ? kTriangle[k] : kEdges[k];
    // g(t) = n . ((q - a) x (b - a)), q, a, b linear in t: a quadratic g0 + g1 t + g2 t^2.
    const Vec3 qa = x0[s[0]] - x0[s[1]], ba = x0[s[2]] - x0[s[1]];
    const Vec3 dqa = d[s[0]] - d[s[1]], dba = d[s[2]] - d[s[1]];
    quadraticRoots(normal.dot(dqa.cross(dba)), normal.dot(qa.cross(dba) + dqa.cross(ba)), normal.dot(qa.cross(ba)),
                   times);
  }
  std::sort(times.begin(), times.end());
  times.erase(std::unique(times.begin(), times.end()), times.end());
}

Closest closest(Primitive kind, const std::array<Vec3, 4>& x) {
  return kind == Primitive::PointTriangle ? pointTriangle(x[0], x[1], x[2], x[3]) : edgeEdge(x[0], x[1], x[2], x[3]);
}

}  // namespace

std::array<double, 4> coplanarityCubic(const Vec3& p, const Vec3& b, const Vec3& c, const Vec3& dp, const Vec3& db,
                                       const Vec3& dc) {
  const Vec3 bc = b.cross(c), mixed = b.cross(dc) + db.cross(c), dbdc = db.cross(dc);
  return {p.dot(bc), p.dot(mixed) + dp.dot(bc), p.dot(dbdc) + dp.dot(mixed), dp.dot(dbdc)};
}

void candidateTimes(const std::array<double, 4>& cubic, std::vector<double>& out) {
  out.clear();
  std::vector<double> cuts;  // f is monotone between consecutive cuts
  cuts.push_back(0);
  quadraticRoots(3 * cubic[3], 2 * cubic[2], cubic[1], cuts);
  std::sort(cuts.begin() + 1, cuts.end());
  cuts.push_back(1);
  for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
    const double lo = cuts[k], hi = cuts[k + 1];
    const double flo = evaluate(cubic, lo), fhi = evaluate(cubic, hi);
    if (flo == 0) out.push_back(lo);
    else if ((flo < 0) != (fhi < 0) && fhi != 0) out.push_back(bisect(cubic, lo, hi, flo));
    if (k + 1 < cuts.size() - 1) out.push_back(hi);  // an extremum: a touching root or a near miss
  }
  out.push_back(1);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

std::optional<Hit> firstHit(Primitive kind, const std::array<Vec3, 4>& x0, const std::array<Vec3, 4>& x1, double eta) {
  std::array<Vec3, 4> d;
  for (int i = 0; i < 4; ++i) d[i] = x1[i] - x0[i];
  // The same cubic serves both primitives: point-triangle (p, a, b, c) and edge-edge (a0, a1, b0, b1) are four
  // points, coplanar at a contact either way.
  const auto cubic =
      coplanarityCubic(x0[1] - x0[0], x0[2] - x0[0], x0[3] - x0[0], d[1] - d[0], d[2] - d[0], d[3] - d[0]);
  thread_local std::vector<double> times;
  candidateTimes(cubic, times);
  // Coplanar all along (f = 0 to rounding): the elements meet in their plane, where a point crosses the other
  // element's edge line; those times are the roots of quadratics n . ((q - a) x (b - a)) for the plane's normal n.
  double scale2 = 0;
  for (int i = 1; i < 4; ++i) scale2 = std::max({scale2, (x0[i] - x0[0]).squaredNorm(), (x1[i] - x1[0]).squaredNorm()});
  const double size3 = scale2 * std::sqrt(scale2);
  if (std::abs(cubic[0]) + std::abs(cubic[1]) + std::abs(cubic[2]) + std::abs(cubic[3]) <= 1e-12 * size3)
    addInPlaneTimes(kind, x0, d, times);
  std::optional<Closest> start;  // computed when first needed: most pairs never get that far
  for (const double t : times) {
    std::array<Vec3, 4> x;
    for (int i = 0; i < 4; ++i) x[i] = x0[i] + t * d[i];
    // |f| is six times the volume of the four points' tetrahedron: the triangle's area times twice the point's
    // height over its plane, or |d1 x d2| times the distance between the edges' lines. So |f| / (|e1| |e2|), with e1,
    // e2 the triangle's edges or the two edges, bounds the distance from below: at least eta, the pair is apart.
    const double e1 = kind == Primitive::PointTriangle ? (x[2] - x[1]).norm() : (x[1] - x[0]).norm();
    const double e2 = kind == Primitive::PointTriangle ? (x[3] - x[1]).norm() : (x[3] - x[2]).norm();
    if (std::abs(evaluate(cubic, t)) > 1.01 * eta * e1 * e2) continue;
    const Closest at = closest(kind, x);
    if (at.distance >= eta) continue;
    // The normal: the plane's (triangle normal, or the two edges' cross product) at t, oriented along the relative
    // position at the start; when the plane degenerates, the start's relative position itself.
    Vec3 normal = kind == Primitive::PointTriangle ? Vec3((x[2] - x[1]).cross(x[3] - x[1]))
                                                   : Vec3((x[1] - x[0]).cross(x[3] - x[2]));
    const double length = normal.norm();
    Vec3 start_delta = Vec3::Zero();
    for (int i = 0; i < 4; ++i) start_delta += at.w[i] * x0[i];
    if (length > 1e-12 * (x[1] - x[0]).squaredNorm() && length > 0) {
      normal /= length;
      if (normal.dot(start_delta) < 0) normal = -normal;
    } else if ((start ? start : (start = closest(kind, x0)))->distance > 0) {
      normal = start->delta / start->distance;
    } else {
      continue;
    }
    Vec3 relative_velocity = Vec3::Zero();
    for (int i = 0; i < 4; ++i) relative_velocity += at.w[i] * d[i];
    if (normal.dot(relative_velocity) >= 0) continue;  // separating or sliding: no collision here
    return Hit{t, at, normal};
  }
  return std::nullopt;
}

}  // namespace wobble::collision
