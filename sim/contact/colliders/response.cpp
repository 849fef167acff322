#include "sim/contact/colliders/response.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

namespace wobble {
namespace {

std::vector<int>& nearScratch() {
  thread_local std::vector<int> near;  // kept between calls: no allocation per step
  return near;
}

// The step end's velocity change of a point within the band (restitution on its approach), and its move onto the
// surface when it is below it. v_start (when known): the point's velocity at the step's start. The bounce is the
// restitution times the approach the point brought into the step, at most the end's: the approach the step's own
// forces added (a resting point's load, a h a step) is resting contact, stopped with restitution 0 (Guendelman,
// Bridson & Fedkiw 2003: contact apart from the collisions), so a point resting on a bouncy surface does
// not hop. An impact brings its approach from the step's start, and keeps its bounce (less the speed one step's
// acceleration adds, at most).
struct Response {
  Vec3 dv = Vec3::Zero(), dx = Vec3::Zero();
};
Response response(const SurfacePoint& s, const ContactParams& c, const Vec3& v, const Vec3* v_start) {
  Response r;
  const double vn = s.normal.dot(v - s.velocity);
  if (vn < 0) {
    double approach = -vn;
    if (v_start) approach = std::min(approach, std::max(0.0, -s.normal.dot(*v_start - s.velocity)));
    r.dv = (-vn + c.restitution * approach) * s.normal;
  }
  if (s.distance < 0) r.dx = -s.distance * s.normal;
  return r;
}

// The response of a point near collider at t (nothing outside its band), for both kinds of point: read(y) is the
// point's value of a per-particle vector y (a particle's own, or the blend of a riding point's particles), so its
// position is read(x), its velocity read(v), and its start velocity read(*v_start) when known.
template <class Read>
std::optional<Response> respond(const Collider& collider, double t, const VecX& x, const VecX& v, const VecX* v_start,
                                const Read& read) {
  const auto s = collider.query(t, read(x));
  if (!s || s->distance >= collider.contact().epsilon) return std::nullopt;
  const Vec3 start = v_start ? read(*v_start) : Vec3::Zero();
  return response(*s, collider.contact(), read(v), v_start ? &start : nullptr);
}

}  // namespace

SupportParts supportParts(const SurfacePoint& s, const ContactParams& c, const Vec3& f, const Vec3& v, double m,
                          double stick_time) {
  // Net force relative to the surface's frame; its normal part pushes into the surface (activeSupport).
  const Vec3 g = f - m * s.acceleration;
  const double push = s.normal.dot(g), support = -push;
  const Vec3 vr = v - s.velocity;
  const Vec3 vt = vr - s.normal.dot(vr) * s.normal;
  const Vec3 gt = g - push * s.normal;
  const double limit = c.friction * support;
  Vec3 friction = -(gt + (m / stick_time) * vt);
  const bool sticks = !(friction.norm() > limit);
  if (!sticks) {
    const double speed = vt.norm();
    const Vec3 direction = speed > 0 ? Vec3(vt / speed) : gt.normalized();
    friction = -limit * direction;
  }
  return {support, friction, limit, sticks};
}

Vec3 supportForce(const SurfacePoint& s, const ContactParams& c, const Vec3& f, const Vec3& v, double m,
                  double stick_time) {
  const SupportParts p = supportParts(s, c, f, v, m, stick_time);
  return p.support * s.normal + p.friction;
}

std::optional<SurfacePoint> activeSupport(const Collider& collider, double t, const Vec3& x, const Vec3& f, double m) {
  auto s = collider.query(t, x);
  if (!s || std::abs(s->distance) >= collider.contact().epsilon) return std::nullopt;
  if (s->normal.dot(f - m * s->acceleration) >= 0) return std::nullopt;
  return s;
}

void addContactForces(Colliders colliders, double t, const VecX& x, const VecX& v, const VecX& mass,
                      const VecX& inv_mass, double stick_time, VecX& f) {
  // Collider by collider over the particles near it: each particle still meets the colliders in order.
  std::vector<int>& near = nearScratch();
  for (const auto& collider : colliders) {
    collider->near(t, x, collider->contact().epsilon, near);
    for (const int i : near) {
      if (inv_mass[i] == 0) continue;
      const auto s = activeSupport(*collider, t, particle(x, i), particle(f, i), mass[i]);
      if (!s) continue;
      particle(f, i) += supportForce(*s, collider->contact(), particle(f, i), particle(v, i), mass[i], stick_time);
    }
  }
}

void resolveCollisions(Colliders colliders, double t, VecX& x, VecX& v, const VecX& inv_mass, const VecX* v_start) {
  std::vector<int>& near = nearScratch();
  for (const auto& collider : colliders) {
    collider->near(t, x, collider->contact().epsilon, near);
    for (const int i : near) {
      if (inv_mass[i] == 0) continue;
      const auto r = respond(*collider, t, x, v, v_start, [i](const VecX& y) { return Vec3(particle(y, i)); });
      if (!r) continue;
      particle(v, i) += r->dv;
      particle(x, i) += r->dx;
    }
  }
}

namespace {

// nearPoints' candidates for a half-space: the points whose blended distance is within reach of the plane.
void halfSpaceCandidates(const HalfSpace& half, const WeightedPoints& points, const VecX& x, double margin,
                         std::vector<int>& out) {
  thread_local VecX d;  // each particle's distance, as near() computes it
  const Eigen::Index n = x.size() / 3;
  if (d.size() != n) d.resize(n);  // once
  for (Eigen::Index i = 0; i < n; ++i) d[i] = half.normal.dot(particle(x, i) - half.point);
  const double reach = margin + roundOffSlack(x.cwiseAbs().maxCoeff() + half.point.cwiseAbs().maxCoeff());
  for (int c = 0; c < points.cellCount(); ++c) {
    const std::array<int, 8>& k = points.cellParticles(c);
    const double dk[8] = {d[k[0]], d[k[1]], d[k[2]], d[k[3]], d[k[4]], d[k[5]], d[k[6]], d[k[7]]};
    if (*std::min_element(dk, dk + 8) >= reach) continue;
    points.cellPointsBelow(c, dk, reach, out);  // those with blendValue(d, p) < reach
  }
  std::sort(out.begin(), out.end());  // cell by cell: back to index order
}

}  // namespace

void nearPoints(const Collider& collider, double t, const WeightedPoints& points, const VecX& x, CellBoxes& cells,
                double margin, std::vector<int>& out, VecX& at) {
  thread_local std::vector<char> cell_near;
  thread_local std::vector<int> kept;  // indices into out
  out.clear();
  out.reserve(points.size());                                       // once
  if (at.size() < 3 * points.size()) at.resize(3 * points.size());  // once
  if (const auto half = collider.halfSpace(t)) {
    halfSpaceCandidates(*half, points, x, margin, out);
  } else {
    const std::vector<Eigen::AlignedBox3d>& boxes = cells.of(points, x);
    cell_near.resize(points.cellCount());
    bool any = false;
    for (int c = 0; c < points.cellCount(); ++c) any |= (cell_near[c] = collider.mayBeNear(t, boxes[c], margin));
    if (any)
      for (int p = 0; p < points.size(); ++p)
        if (cell_near[points.cell(p)]) out.push_back(p);
  }
  if (out.empty()) return;
  points.blendSome(x, out, at);
  collider.near(t, at.head(3 * Eigen::Index(out.size())), margin, kept);
  for (std::size_t j = 0; j < kept.size(); ++j) {  // kept[j] >= j: moved forward in place
    out[j] = out[kept[j]];
    particle(at, Eigen::Index(j)) = particle(at, kept[j]);
  }
  out.resize(kept.size());
}

void addContactForces(Colliders colliders, const WeightedPoints& points, double t, const VecX& x, const VecX& v,
                      const VecX& inv_mass, double stick_time, VecX& f, std::vector<ReleasedSupport>* added) {
  if (points.empty() || colliders.empty()) return;
  thread_local VecX at;  // the near points' positions
  thread_local CellBoxes cells;
  thread_local std::vector<int> near;
  cells.clear();
  // Point by point (Gauss-Seidel): a point sees the support its neighbours in the same cell already have.
  for (const auto& collider : colliders) {
    nearPoints(*collider, t, points, x, cells, collider->contact().epsilon, near, at);
    for (std::size_t j = 0; j < near.size(); ++j) {
      const int p = near[j];
      if (points[p].inverse_mass == 0) continue;
      const double m = 1 / points[p].inverse_mass;
      const Vec3 fp = m * points.acceleration(f, inv_mass, p);
      const auto s = activeSupport(*collider, t, particle(at, Eigen::Index(j)), fp, m);
      if (!s) continue;
      const Vec3 g = supportForce(*s, collider->contact(), fp, points.blend(v, p), m, stick_time);
      points.spread(p, g, f);
      if (added)
        for (int k = 0; k < 8; ++k)  // a point on a cell's face or edge has corners of weight 0: nothing to release
          if (points[p].weight[k] != 0) added->push_back({points[p].particle[k], points[p].weight[k] * g});
    }
  }
}

void resolveCollisions(Colliders colliders, const WeightedPoints& points, double t, VecX& x, VecX& v,
                       const VecX& inv_mass, const VecX* v_start) {
  if (points.empty()) return;
  thread_local VecX at;
  thread_local CellBoxes cells;
  thread_local std::vector<int> near;
  for (const auto& collider : colliders) {
    cells.clear();  // where the colliders before this one left the points
    nearPoints(*collider, t, points, x, cells, collider->contact().epsilon, near, at);
    for (const int p : near) {
      if (points[p].inverse_mass == 0) continue;
      // At the point's blend of x as the points before it left it.
      const auto r = respond(*collider, t, x, v, v_start, [&points, p](const VecX& y) { return points.blend(y, p); });
      if (!r) continue;
      points.shift(p, r->dv, inv_mass, v);
      points.shift(p, r->dx, inv_mass, x);
    }
  }
}

}  // namespace wobble
