// Points that ride on particles with fixed weights: a mesh jelly's model vertices, each the trilinear blend of its
// lattice cell's 8 particles (bodies/mesh_jelly.h). Contact treats such a point as a particle of its own: it meets
// colliders where it is, and what contact does to it (a force, an impulse, a displacement) is handed to its particles
// by the same weights, scaled so that the point itself gets exactly that change (the embedded-surface contact of
// Sifakis, Shinar, Irving & Fedkiw 2007, "Hybrid simulation of deformable solids", and McAdams et al. 2011,
// "Efficient elasticity for character skinning with contact and collisions": collision proxies on the embedded
// surface, their response distributed through the interpolation weights).
//
// A point p = sum_k w_k x_k with weights w_k >= 0 summing to 1. An impulse J at p, given as w_k J to each particle,
// changes p's velocity by J sum_k w_k^2 / m_k: the point's mass is m_p = 1 / sum_k w_k^2 / m_k (a particle alone:
// its own mass), and a force or impulse on it moves it as it would move a particle of that mass.
//
// Points over the same 8 particles share a cell (a mesh jelly's lattice cell). Since the weights are a convex
// combination, every point of a cell lies in the box of its particles' positions: contact bounds a cell by that box
// and blends only the points of cells a collider may be near (contact/colliders/response.h, nearPoints).
#pragma once
#include <array>
#include <map>
#include <span>
#include <vector>

#include "sim/types.h"

namespace wobble {

struct WeightedPoint {
  std::array<int, 8> particle;   // in the system's flat state
  std::array<double, 8> weight;  // >= 0, summing to 1
  double inverse_mass = 0;       // sum_k w_k^2 / m_k: 0 when every particle with a weight is pinned
};

class WeightedPoints {
 public:
  // Appends a point over particles first + particle[k] of a body, with inverse_mass from the system's inverse masses.
  // The weights must be >= 0 and sum to 1 (within 1e-12): std::invalid_argument otherwise.
  void add(const std::array<int, 8>& particle, const std::array<double, 8>& weight, int first, const VecX& inv_mass);

  int size() const { return static_cast<int>(points_.size()); }
  // The distinct particle sets the points ride on, and the one point p rides on.
  int cellCount() const { return static_cast<int>(cells_.size()); }
  int cell(int p) const { return cell_of_[p]; }
  const std::array<int, 8>& cellParticles(int c) const { return cells_[c]; }
  // The points riding on cell c, ascending.
  std::span<const int> cellPoints(int c) const { return cell_points_[c]; }
  bool empty() const { return points_.empty(); }
  const WeightedPoint& operator[](int p) const { return points_[p]; }

  // sum_k w_k s_k of a flat 3-per-particle vector s (a position, a velocity).
  Vec3 blend(const VecX& s, int p) const {
    const WeightedPoint& w = points_[p];
    Vec3 sum = Vec3::Zero();
    for (int k = 0; k < 8; ++k) sum += w.weight[k] * particle(s, w.particle[k]);
    return sum;
  }
  // sum_k w_k s_k of a vector s of one value per particle.
  double blendValue(const VecX& s, int p) const {
    const WeightedPoint& w = points_[p];
    double sum = 0;
    for (int k = 0; k < 8; ++k) sum += w.weight[k] * s[w.particle[k]];
    return sum;
  }
  // Appends to out the points of cell c whose blendValue of s is below limit, in cellPoints(c)'s order, from the
  // cell's particles' values s[0 .. 7] (cellParticles(c)'s order): the same sums and the same test as
  // blendValue(s, p) < limit, taken four points at a time.
  void cellPointsBelow(int c, const double* s, double limit, std::vector<int>& out) const;
  // Every point's blend of s, 3 per point (resized).
  void blendAll(const VecX& s, VecX& out) const;
  // The blends of the points listed, 3 per listed point, the same sums as blendAll's, at the head of out (which grows
  // to fit and is never shrunk: a buffer sized once).
  void blendSome(const VecX& s, std::span<const int> which, VecX& out) const;
  // Each cell's box: the bounds of its particles in the positions x, which hold every point riding on it, widened by
  // the blend's round-off (out resized).
  void cellBounds(const VecX& x, std::vector<Eigen::AlignedBox3d>& out) const;
  // The point's acceleration under the particle forces f: sum_k w_k f_k / m_k.
  Vec3 acceleration(const VecX& f, const VecX& inv_mass, int p) const;
  // Hands the force (or impulse) g at point p to its particles: out_k += w_k g.
  void spread(int p, const Vec3& g, VecX& out) const;
  // Changes the point's own state by d through its particles: s_k += (w_k / m_k) m_p d, so blend(s, p) moves by d
  // (a velocity change from an impulse m_p d, or a displacement).
  void shift(int p, const Vec3& d, const VecX& inv_mass, VecX& s) const;

 private:
  std::vector<WeightedPoint> points_;
  std::vector<std::array<int, 8>> cells_;  // the particles of each cell, as the first point on it listed them
  std::vector<int> cell_of_;               // per point
  std::vector<std::vector<int>> cell_points_;
  // Each cell's points' weights four points at a time, weight[k][lane] (lanes past the last point 0): the layout
  // cellPointsBelow reads with one vector operation per particle.
  struct WeightQuad {
    alignas(32) double weight[8][4];
  };
  std::vector<std::vector<WeightQuad>> cell_weights_;
  std::map<std::array<int, 8>, int> cell_index_;
};

}  // namespace wobble
