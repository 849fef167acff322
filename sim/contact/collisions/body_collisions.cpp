#include "sim/contact/collisions/body_collisions.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <iterator>
#include <numeric>
#include <span>
#include <sstream>
#include <tuple>
#include <type_traits>

#include "sim/contact/broad_phase/broad_phase.h"
#include "sim/contact/ccd/ccd.h"
#include "sim/contact/pair_set.h"
#include "sim/solver/parallel.h"
#include "sim/surface.h"

namespace wobble::collision {
namespace {

// Collisions are reported within this fraction of the pair's thickness (ccd.h's eta): the cubic's roots are exact to
// rounding, so this only has to cover a touching root and the rounding of the closest-point query.
constexpr double kEtaFraction = 1e-3;
// Repulsion pushes apart at most this fraction of the thickness left per step (Bridson 2002, 7.2: 0.1 d / h).
constexpr double kRepulsionFraction = 0.1;
// The step's candidates (Impl::StepCandidates) are found with boxes padded by this fraction of the largest thickness
// more than the exact broad phase's: room for the solves' ends to move from the first one's.
constexpr double kStepMarginFraction = 0.25;
// The pass's candidates kept across steps (Impl::Skin) are found with boxes padded by this fraction of the largest
// thickness more than the exact broad phase's, and serve while every node stays within half of it of the box it swept.
constexpr double kSkinFraction = 0.5;
// Backward Euler's step lists are kept across steps (Impl::StepSkin) with each node's interval reaching this fraction
// of the largest thickness beyond its start and end, each way.
constexpr double kNodeSlackFraction = 0.5;
// A collision impulse leaves at most this fraction of the approach speed as separation (no restitution beyond it),
// and aims to end the step this fraction of the thickness apart.
constexpr double kSeparation = 0.1, kEndGapFraction = 0.01;

// Extents along the six diagonals of a box's axes, x + y, x - y, y + z, y - z, z + x, z - x (Impl::diagonals).
struct Diagonals {
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  std::array<double, 6> lo{kInf, kInf, kInf, kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf, -kInf, -kInf, -kInf};  // empty
  void include(const Vec3& p) {
    const std::array<double, 6> d{p.x() + p.y(), p.x() - p.y(), p.y() + p.z(),
                                  p.y() - p.z(), p.z() + p.x(), p.z() - p.x()};
    for (int k = 0; k < 6; ++k) lo[k] = std::min(lo[k], d[k]), hi[k] = std::max(hi[k], d[k]);
  }
  // Every point of the box [a, b]: each sum or difference at its least and greatest (rounding is monotone, so a
  // point's own rounded sums lie within these).
  void include(const Vec3& a, const Vec3& b) {
    const std::array<double, 6> l{a.x() + a.y(), a.x() - b.y(), a.y() + a.z(),
                                  a.y() - b.z(), a.z() + a.x(), a.z() - b.x()};
    const std::array<double, 6> h{b.x() + b.y(), b.x() - a.y(), b.y() + b.z(),
                                  b.y() - a.z(), b.z() + b.x(), b.z() - a.x()};
    for (int k = 0; k < 6; ++k) lo[k] = std::min(lo[k], l[k]), hi[k] = std::max(hi[k], h[k]);
  }
};

// Each element's box and diagonals (those of a broad phase, or of a skin's intervals).
struct ElementBoxes {
  std::vector<Box> vertex, edge, triangle;
  std::vector<Diagonals> vertex_diagonals, edge_diagonals, triangle_diagonals;
};

struct PairInfo {
  Primitive kind;
  Stencil stencil;
  double thickness, friction, stiffness;
  // The first element's nodes: stencil.vertex[0, first()) (a point, or an edge), the second's the rest.
  int first() const { return kind == Primitive::PointTriangle ? 1 : 2; }
};

// The nearest points of a pair's two elements, whose nodes are at x (in stencil order).
Closest nearest(Primitive kind, const std::array<Vec3, 4>& x) {
  return kind == Primitive::PointTriangle ? pointTriangle(x[0], x[1], x[2], x[3]) : edgeEdge(x[0], x[1], x[2], x[3]);
}

// A point-triangle or edge-edge pair found near (proximity) or colliding (hit).
struct Contact {
  int pair;  // index into the round's candidate list
  Closest at;
  Vec3 normal;
  double t;  // hit time (0 for a proximity)
};

class UnionFind {
 public:
  void reset(int n) {
    parent_.resize(n);
    std::iota(parent_.begin(), parent_.end(), 0);
  }
  int find(int i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  // The smaller root becomes the parent: zones are the same whatever the order of merges.
  void merge(int a, int b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<int> parent_;
};

std::atomic<bool> motion_cull{true};

}  // namespace

void setBroadPhaseCulls(bool on) { motion_cull = on; }

struct BodyCollisions::Impl {
  // The surfaces' vertices as nodes, each a weighted blend of particles (weights summing to 1): one particle of
  // weight 1 for a surface over particles, a lattice cell's 8 particles for a mesh jelly's embedded surface
  // (contact/colliders/weighted_points.h). Node k's particles are node_particle[node_start[k] .. node_start[k + 1]).
  // Every node is a vertex of the pass (vertex slot k is node k); triangles and edges are in node indices, each with
  // its body. A node's trajectory over the step is the blend of its particles' straight trajectories, itself straight:
  // the continuous test holds on it as on a particle's, and an impulse on it is handed to its particles by the weights.
  std::vector<int> node_start{0}, node_particle;
  std::vector<double> node_weight;
  std::vector<int> particle_node_start, particle_nodes;  // per particle, the nodes over it (CSR)
  std::vector<int> pass_particles;                       // every particle a node rides on, ascending
  std::vector<double> node_inv_mass;                     // sum w^2 / m over a node's particles
  bool single_particle_nodes = true;  // no surface of embedded points: each node its own particle, of weight 1
  std::vector<std::array<int, 3>> triangles;
  std::vector<std::array<int, 2>> edges;
  std::vector<int> triangle_body, edge_body, vertex_body;
  std::vector<std::array<int, 1>> single_nodes;  // each node as a one-node element (the vertices' boxes)
  std::vector<SurfaceContact> params;
  std::vector<double> stiffness;
  const VecX& inv_mass;
  Settings settings;
  bool parallel;
  double max_thickness = 0;
  bool cull = true;           // setBroadPhaseCulls, read once a broad phase
  Stats* counters = nullptr;  // the owner's, for the broad phases' counts

  // Per step
  VecX xs;                     // the step's start positions
  VecX vbar, vbar0, xe;        // trajectory velocity (changed and at the start), trajectory end
  VecX nxs, nxe, nvbar;        // the same of the nodes (blends of the particles')
  std::vector<char> changed;   // per particle: vbar changed this step
  std::vector<char> dirty;     // per node: moved since the last detection
  std::vector<int> node_mark;  // per node: the last impulse that refreshed it (refreshNodes)
  int mark = 0;
  ElementBoxes boxes;                                          // the last broad phase's
  std::vector<char> vertex_moved, edge_moved, triangle_moved;  // per element: a node of it is dirty
  std::vector<std::pair<int, int>> vf, ee;                     // candidate pairs: (vertex slot, triangle), (edge, edge)
  // How a broad phase found vf and ee: the frames its boxes were swept in (frameShifts; empty: the world's) and their
  // padding (the step skin's list, cut down to a broad phase's in the world's frame, sets them too). The pass's list
  // kept from an earlier step (keptCandidates) leaves them as they were: it only serves the pass.
  struct Frames {
    std::vector<Vec3> shifts;
    double pad = 0;
  } listed;
  UnionFind zones;
  std::vector<int> root;  // zones.find of each pass particle, for the threads of a detection round

  int nodeCount() const { return int(node_start.size()) - 1; }

  Impl(const std::vector<Surface>& surfaces, const VecX& inverse_mass, Settings s, bool threads)
      : inv_mass(inverse_mass), settings(s), parallel(threads) {
    const int n = int(inverse_mass.size());
    for (std::size_t b = 0; b < surfaces.size(); ++b) {
      const Surface& surface = surfaces[b];
      const SurfaceMesh& mesh = *surface.mesh;
      params.push_back(surface.params);
      stiffness.push_back(surface.stiffness);
      max_thickness = std::max(max_thickness, surface.params.thickness);
      // The body's nodes: the particles (or embedded points) its triangles use, ascending; a triangle with two
      // corners on one is left out.
      std::vector<std::array<int, 3>> body_triangles;
      for (const auto& t : mesh.triangles) {
        const std::array<int, 3> p{mesh.particle[t[0]], mesh.particle[t[1]], mesh.particle[t[2]]};
        if (p[0] != p[1] && p[1] != p[2] && p[0] != p[2]) body_triangles.push_back(p);
      }
      std::vector<int> used;
      for (const auto& t : body_triangles) used.insert(used.end(), t.begin(), t.end());
      std::sort(used.begin(), used.end());
      used.erase(std::unique(used.begin(), used.end()), used.end());
      std::vector<int> node(used.empty() ? 0 : used.back() + 1, -1);
      single_particle_nodes = single_particle_nodes && mesh.embedded.empty();
      for (const int u : used) {
        node[u] = nodeCount();
        vertex_body.push_back(int(b));
        if (mesh.embedded.empty()) {
          node_particle.push_back(surface.first_particle + u);
          node_weight.push_back(1.0);
        } else {
          const EmbeddedPoint& e = mesh.embedded[u];
          for (int k = 0; k < 8; ++k)
            if (e.weight[k] != 0) {
              node_particle.push_back(surface.first_particle + e.particle[k]);
              node_weight.push_back(e.weight[k]);
            }
        }
        node_start.push_back(int(node_particle.size()));
      }
      std::vector<std::array<int, 2>> body_edges;
      for (const auto& t : body_triangles) {
        const std::array<int, 3> p{node[t[0]], node[t[1]], node[t[2]]};
        triangles.push_back(p);
        triangle_body.push_back(int(b));
        for (int k = 0; k < 3; ++k)
          body_edges.push_back({std::min(p[k], p[(k + 1) % 3]), std::max(p[k], p[(k + 1) % 3])});
      }
      std::sort(body_edges.begin(), body_edges.end());
      body_edges.erase(std::unique(body_edges.begin(), body_edges.end()), body_edges.end());
      edges.insert(edges.end(), body_edges.begin(), body_edges.end());
      edge_body.insert(edge_body.end(), body_edges.size(), int(b));
    }
    // Per particle its nodes, and the nodes' inverse masses.
    particle_node_start.assign(n + 1, 0);
    for (const int p : node_particle) ++particle_node_start[p + 1];
    for (int p = 0; p < n; ++p) particle_node_start[p + 1] += particle_node_start[p];
    particle_nodes.resize(node_particle.size());
    std::vector<int> fill(particle_node_start.begin(), particle_node_start.end() - 1);
    node_inv_mass.assign(nodeCount(), 0.0);
    for (int k = 0; k < nodeCount(); ++k)
      for (int j = node_start[k]; j < node_start[k + 1]; ++j) {
        particle_nodes[fill[node_particle[j]]++] = k;
        node_inv_mass[k] += node_weight[j] * node_weight[j] * inv_mass[node_particle[j]];
      }
    for (int p = 0; p < n; ++p)
      if (particle_node_start[p + 1] > particle_node_start[p]) pass_particles.push_back(p);
    node_mark.assign(nodeCount(), 0);
    single_nodes.resize(nodeCount());
    for (int k = 0; k < nodeCount(); ++k) single_nodes[k] = {k};
  }

  // Node k's blend of a flat per-particle vector s, into out (3 per node); a node of one particle of weight 1 copies.
  void blendNode(const VecX& s, int k, VecX& out) const {
    const int begin = node_start[k], end = node_start[k + 1];
    if (end - begin == 1 && node_weight[begin] == 1) {
      particle(out, k) = particle(s, node_particle[begin]);
      return;
    }
    Vec3 sum = Vec3::Zero();
    for (int j = begin; j < end; ++j) sum += node_weight[j] * particle(s, node_particle[j]);
    particle(out, k) = sum;
  }
  void blendNodes(const VecX& s, VecX& out) const {
    out.resize(3 * nodeCount());
    forEachChunk(nodeCount(), parallel, [&](int begin, int end) {
      for (int k = begin; k < end; ++k) blendNode(s, k, out);
    });
  }
  // After particles' vbar and xe changed: their nodes' nvbar and nxe again, each node once, marked dirty.
  template <class Particles>
  void refreshNodes(const Particles& moved) {
    ++mark;
    for (const int p : moved)
      for (int j = particle_node_start[p]; j < particle_node_start[p + 1]; ++j) {
        const int k = particle_nodes[j];
        if (node_mark[k] == mark) continue;
        node_mark[k] = mark;
        blendNode(vbar, k, nvbar);
        blendNode(xe, k, nxe);
        dirty[k] = 1;
      }
  }
  // The particle of node k with the largest weight (for messages).
  int mainParticle(int k) const {
    int best = node_start[k];
    for (int j = node_start[k]; j < node_start[k + 1]; ++j)
      if (node_weight[j] > node_weight[best]) best = j;
    return node_particle[best];
  }
  // The stencil of a pair over nodes with weights w (Stencil), over the nodes' particles: sum_i w_i sum_j W_ij x_j.
  WeightedStencil expand(const Stencil& s, const std::array<double, 4>& w) const {
    WeightedStencil out;
    for (int i = 0; i < 4; ++i)
      for (int j = node_start[s.vertex[i]]; j < node_start[s.vertex[i] + 1]; ++j)
        out.add(node_particle[j], w[i] * node_weight[j]);
    return out;
  }

  bool bodiesMeet(int a, int b) const { return a != b || params[a].self_contact; }

  double pairThickness(int a, int b) const { return std::max(params[a].thickness, params[b].thickness); }

  // The stencil's vertices of a point-triangle (first: the vertex, second: the triangle) or edge-edge pair.
  std::array<int, 4> nodes(Primitive kind, int first, int second) const {
    if (kind == Primitive::PointTriangle) {
      const auto& t = triangles[second];
      return {first, t[0], t[1], t[2]};
    }
    return {edges[first][0], edges[first][1], edges[second][0], edges[second][1]};
  }
  PairInfo info(Primitive kind, int first, int second) const {
    PairInfo p;
    p.kind = kind;
    p.stencil.vertex = nodes(kind, first, second);
    const bool vf = kind == Primitive::PointTriangle;
    const int a = vf ? vertex_body[first] : edge_body[first], b = vf ? triangle_body[second] : edge_body[second];
    p.thickness = pairThickness(a, b);
    p.friction = 0.5 * (params[a].friction + params[b].friction);
    p.stiffness = 0.5 * (stiffness[a] + stiffness[b]);
    return p;
  }

  // The extents along the six diagonals x + y, x - y, y + z, y - z, z + x, z - x of what a box (below) bounds, the
  // points' swept hull grown by a cube of half-side pad: each of the points' own, grown by 2 pad (the cube's reach
  // along a diagonal). Two elements whose padded hulls meet overlap along every diagonal, as along every axis; where
  // their boxes overlap but a diagonal parts them, they do not meet. Box and diagonals make an 18-DOP (Klosowski et
  // al. 1998, "Efficient collision detection using bounding volume hierarchies of k-DOPs"; for cloth, Mezger,
  // Kimmerle & Etzmuss 2003, "Hierarchical techniques in collision detection for cloth animation"). On a cloth the
  // boxes of a diagonal edge and of a triangle cover a whole cell, and reach its corner vertices and the edges there,
  // some 0.7 spacings away: the diagonals drop those pairs.
  template <class Points>
  Diagonals diagonals(const Points& points, double pad, const VecX& end_x, const Vec3& shift) const {
    Diagonals out;
    for (const int i : points) out.include(particle(nxs, i)), out.include(particle(end_x, i) - shift);
    for (int k = 0; k < 6; ++k) out.lo[k] -= 2 * pad, out.hi[k] += 2 * pad;
    return out;
  }
  // Whether a diagonal parts two extents (above). The sums' rounding (a few ulps of the coordinates) is allowed for: a
  // gap within it is taken as none.
  static bool diagonallyApart(const Diagonals& a, const Diagonals& b) {
    for (int k = 0; k < 6; ++k) {
      const double scale = std::max({std::abs(a.lo[k]), std::abs(a.hi[k]), std::abs(b.lo[k]), std::abs(b.hi[k])});
      const double rounding = 1e-14 * scale;
      if (b.lo[k] - a.hi[k] > rounding || a.lo[k] - b.hi[k] > rounding) return true;
    }
    return false;
  }

  // The box the points sweep from nxs to end_x, in a frame that moves by `shift` over the step (zero: the world's),
  // padded.
  template <class Points>
  Box box(const Points& points, double pad, const VecX& end_x, const Vec3& shift) const {
    Box out{Vec3::Constant(std::numeric_limits<double>::infinity()),
            Vec3::Constant(-std::numeric_limits<double>::infinity())};
    for (const int i : points) {
      const Vec3 end = particle(end_x, i) - shift;
      out.lo = out.lo.cwiseMin(particle(nxs, i)).cwiseMin(end);
      out.hi = out.hi.cwiseMax(particle(nxs, i)).cwiseMax(end);
    }
    out.lo.array() -= pad;
    out.hi.array() -= -pad;
    return out;
  }

  // Whether the elements a (na nodes) and b (nb nodes) are further apart than gap all through the step, by a
  // fixed axis that separates them by more than gap at both ends. Along a fixed axis each point's projection is
  // linear in s, so the gap between the elements' projections (the smallest of one's minus the largest of the
  // other's) is concave in s and at least its value at an end: more than gap at both ends, more all along, and the
  // distance is at least that gap. The axes are x, y and z: the swept boxes overlap when the elements move together
  // (a falling cloth), their boxes at each end mostly do not.
  bool apartAllStep(const int* a, int na, const int* b, int nb, double gap) const {
    if (!cull) return false;
    for (int k = 0; k < 3; ++k) {
      bool ab = true, ba = true;  // a below b all along, b below a all along
      for (const VecX* x : {&nxs, &nxe}) {
        const auto along_axis = [&](int node) { return (*x)[3 * node + k]; };
        const Extent ea = extent(a, na, along_axis), eb = extent(b, nb, along_axis);
        ab = ab && eb.lo - ea.hi > gap;
        ba = ba && ea.lo - eb.hi > gap;
      }
      if (ab || ba) return true;
    }
    return false;
  }

  // Whether the elements (nodes q[0, first) and q[first, 4)) stay further apart than twice eta all through the step
  // along the direction of their nearest points at the start, c (known: a distance that is not NaN): the fixed axis
  // of apartAllStep, chosen to separate them most at the start. Spares the continuous test most pairs that move
  // together (an explicit integrator's small steps).
  bool apartAlongNearest(const Closest& c, const std::array<int, 4>& q, int first, double thickness) const {
    if (!(c.distance > 0)) return false;
    const Vec3 d = c.delta / c.distance;
    const double eta2 = 2 * kEtaFraction * thickness;
    for (const VecX* x : {&nxs, &nxe})
      if (!(gapAlong(d, *x, q, first) > eta2)) return false;
    return true;
  }

  // The interval of a projection y(node) over count nodes.
  struct Extent {
    double lo = std::numeric_limits<double>::infinity(), hi = -std::numeric_limits<double>::infinity();
  };
  template <class Project>
  static Extent extent(const int* nodes, int count, Project&& y) {
    Extent e;
    for (int i = 0; i < count; ++i) {
      const double v = y(nodes[i]);
      e.lo = std::min(e.lo, v), e.hi = std::max(e.hi, v);
    }
    return e;
  }
  // The gap between the elements q[0, first) and q[first, 4) of a pair along unit d (from the second to the first),
  // at the nodes' positions x: the least projection of the first's nodes minus the greatest of the second's. Along a
  // fixed d it is concave over a linear step, so at least its smaller value at the step's ends, and the distance is at
  // least it.
  static double gapAlong(const Vec3& d, const VecX& x, const std::array<int, 4>& q, int first) {
    const auto along_d = [&](int node) { return d.dot(particle(x, node)); };
    return extent(q.data(), first, along_d).lo - extent(q.data() + first, 4 - first, along_d).hi;
  }

  // The candidate pairs of the swept boxes (padded by half the largest thickness, so that every pair within the
  // thickness at the start or meeting on the way is found). Directly before a detection (after_impulses: a later
  // round, impulses applied since the last broad phase), less the pairs a fixed axis keeps further apart than the
  // thickness all through the step (apartAllStep), which continuous detection would not find (never within eta, a
  // thousandth of it), and only the pairs with a particle moved since the last detection (dirty), the only ones it
  // tests then: the same pairs that detection finds, in the same order. The step's first broad phase keeps them all:
  // repulsion changes the trajectories before that round's detection, which tests apartAllStep per pair.
  // The most candidate pairs a broad phase may list (Settings::candidates_per_vertex, min_candidates).
  std::size_t candidateBudget() const {
    return std::max(std::size_t(std::max(0L, settings.min_candidates)),
                    std::size_t(std::max(0, settings.candidates_per_vertex)) * std::size_t(nodeCount()));
  }

  // A new round's candidates in vf and ee (a broad phase's or a kept list's): what was known of the last is void.
  void newCandidates() {
    cull = motion_cull;
    from_step = false;
    from_skin = false;
    round_closest_valid = false;
  }
  // Per body, the shift of the frame its own pairs are found in (moving frames, below): the median of its nodes'
  // displacements over the step, axis by axis (the motion most of the body shares: when part of a falling cloth has
  // landed, a mean would leave both parts' boxes long). Empty when no body has self-contact.
  std::vector<Vec3> frameShifts() const {
    std::vector<std::vector<double>> moves(3 * params.size());  // per body and axis, its nodes' displacements
    bool any = false;
    for (int k = 0; k < nodeCount(); ++k) {
      const int b = vertex_body[k];
      if (!params[b].self_contact) continue;
      for (int a = 0; a < 3; ++a) moves[3 * b + a].push_back(nxe[3 * k + a] - nxs[3 * k + a]);
      any = true;
    }
    if (!any) return {};
    std::vector<Vec3> shift(params.size(), Vec3::Zero());
    for (std::size_t b = 0; b < params.size(); ++b)
      for (int a = 0; a < 3; ++a) {
        std::vector<double>& m = moves[3 * b + a];
        if (m.empty()) continue;
        std::nth_element(m.begin(), m.begin() + m.size() / 2, m.end());
        shift[b][a] = m[m.size() / 2];
      }
    return shift;
  }
  // Returns false when the lists would exceed the candidate budget (vf and ee are then left empty).
  // Moving frames (with the culls on, unless world_only): a body's pairs with itself are found in a frame that moves
  // with the body's typical motion over the step (frameShifts), its pairs with other bodies in the world's. Every test
  // that follows a broad phase (a distance within the thickness at the start, a gap along a direction at an end, a
  // hit along the step) is of the two elements' relative positions at one instant, which a common translation of both
  // leaves alone: a pair that passes one comes within the padded boxes' reach at that instant in any frame that moves
  // uniformly. In the world frame a falling cloth's swept boxes reach many spacings along its fall, and each overlaps
  // the boxes of its neighbours within one flat layer, which never collide; in the body's frame they are as short as
  // the cloth's deformation in the step. The same contacts in the same order, fewer candidates. A list kept across
  // steps (the skins, keptCandidates) is found in the world frame: it must serve steps with other shifts.
  bool broadPhase(bool after_impulses = false, double margin = 0, bool world_only = false) {
    newCandidates();
    const bool moved_only = after_impulses && cull;
    listed.pad = 0.5 * max_thickness + margin;
    listed.shifts = cull && !world_only ? frameShifts() : std::vector<Vec3>();
    if (moved_only) markElements(dirty);
    const bool found = listPairs(nxe, listed.shifts, listed.pad, moved_only, moved_only, vf, ee);
    if (!found) vf.clear(), ee.clear();
    return found;
  }

  // vertex_moved, edge_moved, triangle_moved: whether an element has a node marked in `node_marks`.
  void markElements(const std::vector<char>& node_marks) {
    const auto mark = [&](const auto& items, std::vector<char>& moved) {
      moved.resize(items.size());
      for (std::size_t k = 0; k < items.size(); ++k) {
        moved[k] = 0;
        for (const int p : items[k]) moved[k] |= node_marks[p];
      }
    };
    mark(single_nodes, vertex_moved);
    mark(edges, edge_moved);
    mark(triangles, triangle_moved);
  }
  // Into vf_out and ee_out, ascending: the pairs whose boxes swept from nxs to `end` (each in its body's frame when
  // shifts is not empty, the world's for pairs of two bodies; padded by pad) overlap. marked: only the pairs with an
  // element marked by markElements; apart: less those apartAllStep keeps apart all through (nxs to nxe). Counts the
  // broad phase; false when it would exceed the candidate budget (the lists are then incomplete).
  bool listPairs(const VecX& end, const std::vector<Vec3>& shifts, double pad, bool marked, bool apart,
                 std::vector<std::pair<int, int>>& vf_out, std::vector<std::pair<int, int>>& ee_out) {
    bool found;
    if (shifts.empty()) {
      fillSweptBoxes(end, nullptr, pad);
      found = findPairs(
          boxes, [&](int a, int b) { return bodiesMeet(a, b); }, marked, apart, vf_out, ee_out, 0);
    } else {
      fillSweptBoxes(end, &shifts, pad);  // each body's pairs with itself in its own frame
      found = findPairs(
          boxes, [&](int a, int b) { return a == b && params[a].self_contact; }, marked, apart, vf_out, ee_out, 0);
      if (found && params.size() > 1) {
        thread_local std::vector<std::pair<int, int>> self_vf, self_ee, other_vf, other_ee;
        self_vf.swap(vf_out), self_ee.swap(ee_out);
        fillSweptBoxes(end, nullptr, pad);  // pairs of two bodies in the world's
        found = findPairs(
            boxes, [&](int a, int b) { return a != b; }, marked, apart, other_vf, other_ee,
            self_vf.size() + self_ee.size());
        vf_out.clear(), ee_out.clear();
        std::merge(self_vf.begin(), self_vf.end(), other_vf.begin(), other_vf.end(), std::back_inserter(vf_out));
        std::merge(self_ee.begin(), self_ee.end(), other_ee.begin(), other_ee.end(), std::back_inserter(ee_out));
      }
    }
    ++counters->broad_phases;
    counters->candidates += long(vf_out.size() + ee_out.size());
    return found;
  }
  // Every element's box (in boxes) swept from nxs to end, each in its body's frame (moving by shifts[body] over the
  // step) or, without shifts, the world's, padded by pad; with the culls, its diagonals too.
  void fillSweptBoxes(const VecX& end, const std::vector<Vec3>* shifts, double pad) {
    fillBoxes(boxes, false, [&](const auto& nodes, int body, Box& box_out, Diagonals& diagonals_out) {
      const Vec3 shift = shifts ? (*shifts)[body] : Vec3::Zero();
      box_out = box(nodes, pad, end, shift);
      if (cull) diagonals_out = diagonals(nodes, pad, end, shift);  // read under the culls only
    });
  }
  // Every element's box and diagonals into out by fill(nodes, body, box, diagonals), on threads; only those of the
  // elements markElements marked when marked_only.
  template <class Fill>
  void fillBoxes(ElementBoxes& out, bool marked_only, Fill&& fill) const {
    const auto each = [&](std::vector<Box>& element_boxes, std::vector<Diagonals>& element_diagonals, const auto& items,
                          const std::vector<int>& body, const std::vector<char>& moved) {
      element_boxes.resize(items.size());
      element_diagonals.resize(items.size());
      forEachChunk(int(items.size()), parallel, [&](int begin, int stop) {
        for (int k = begin; k < stop; ++k)
          if (!marked_only || moved[k]) fill(items[k], body[k], element_boxes[k], element_diagonals[k]);
      });
    };
    each(out.vertex, out.vertex_diagonals, single_nodes, vertex_body, vertex_moved);
    each(out.edge, out.edge_diagonals, edges, edge_body, edge_moved);
    each(out.triangle, out.triangle_diagonals, triangles, triangle_body, triangle_moved);
  }
  // Into vf_found and ee_found, ascending: the pairs whose boxes in b overlap and whose bodies `bodies` accepts, less
  // those of adjacent elements, of pinned nodes only, and (with the culls) those the diagonals part; marked and apart
  // as for listPairs. used: candidates found already (of the budget). False: over the budget.
  template <class Bodies>
  bool findPairs(const ElementBoxes& b, const Bodies& bodies, bool marked, bool apart,
                 std::vector<std::pair<int, int>>& vf_found, std::vector<std::pair<int, int>>& ee_found,
                 std::size_t used) {
    const std::size_t budget = candidateBudget();
    const auto pairs = [&](const std::vector<Box>& queries, const std::vector<Box>& targets, bool same,
                           const std::vector<char>& query_moved, const std::vector<char>& target_moved,
                           const std::function<bool(int, int)>& keep, std::vector<std::pair<int, int>>& out,
                           std::size_t limit) {
      return marked
                 ? overlappingMarkedPairs(queries, targets, same, parallel, query_moved, target_moved, keep, out, limit)
                 : overlappingPairs(queries, targets, same, parallel, keep, out, limit);
    };
    if (!pairs(
            b.vertex, b.triangle, false, vertex_moved, triangle_moved,
            [&](int v, int t) {
              if (!bodies(vertex_body[v], triangle_body[t])) return false;
              const int p = v;
              const auto& tri = triangles[t];
              if (p == tri[0] || p == tri[1] || p == tri[2]) return false;
              const auto& m = node_inv_mass;
              if (!(m[p] + m[tri[0]] + m[tri[1]] + m[tri[2]] > 0)) return false;
              if (cull && diagonallyApart(b.vertex_diagonals[v], b.triangle_diagonals[t])) return false;
              return !apart || !apartAllStep(&p, 1, tri.data(), 3, pairThickness(vertex_body[v], triangle_body[t]));
            },
            vf_found, budget - std::min(budget, used)))
      return false;
    return pairs(
        b.edge, b.edge, true, edge_moved, edge_moved,
        [&](int e, int f) {
          if (!bodies(edge_body[e], edge_body[f])) return false;
          const auto &a = edges[e], &c = edges[f];
          if (a[0] == c[0] || a[0] == c[1] || a[1] == c[0] || a[1] == c[1]) return false;
          const auto& m = node_inv_mass;
          if (!(m[a[0]] + m[a[1]] + m[c[0]] + m[c[1]] > 0)) return false;
          if (cull && diagonallyApart(b.edge_diagonals[e], b.edge_diagonals[f])) return false;
          return !apart || !apartAllStep(a.data(), 2, c.data(), 2, pairThickness(edge_body[e], edge_body[f]));
        },
        ee_found, budget - std::min(budget, used + vf_found.size()));
  }

  // Why the pass stops when the broad phase exceeds its budget: the vertex that moved furthest in the step.
  Failure overwhelmedFailure() const {
    int furthest = 0;
    double most = 0;
    for (int k = 0; k < nodeCount(); ++k) {
      const double move = (particle(nxe, k) - particle(nxs, k)).norm();
      if (move > most || !(move == move)) furthest = k, most = move;
    }
    std::ostringstream why;
    why << "the broad phase would list more than " << candidateBudget() << " candidate pairs in this step ("
        << nodeCount() << " surface vertices): the surfaces moved too far in it (a vertex by " << most
        << " m, against a contact thickness of " << max_thickness << " m)";
    return Failure{mainParticle(furthest), why.str(),
                   "or bodies that start nearer rest (one released under strain can move many particle spacings in "
                   "a step)"};
  }

  // The step's candidates, kept through backward Euler's solves (nearPairs) and the pass after the step (resolve):
  // found once for the swept boxes from the start to the first solve's end, padded by kStepMarginFraction of the
  // thickness more, with each pair's nearest points at the start. They stand while the start is the same bytes and
  // every node's end lies within that margin of the end they were found for: each exact swept box then lies inside
  // its padded one, so the list holds every pair of the exact broad phase, in the same ascending order, and the tests
  // that follow (a distance within the thickness, a gap, a hit along the step) drop the others: the same contacts in
  // the same order, without a broad phase and nearest points again at each solve. (Of those pairs the list keeps the
  // ones a search may test, sortStep; an end with some nodes beyond the margin brings it up to date in part,
  // updateStep. The boxes of a body's pairs with itself are in its moving frame, broadPhase.)
  // Most candidates lie far apart along their nearest points' direction d at the start, and stay so at the end
  // (neighbours within one flat layer of a cloth). Along a fixed unit d each vertex's projection is linear in the
  // step's fraction, so the gap between the two elements' projections (the least of one's minus the greatest of the
  // other's) is concave: at least its smaller value at the ends, and the distance is at least that. An end whose
  // nodes moved by at most `drift` (Euclidean) from the one the candidates were found for changes that gap by at most
  // 2 drift. So each candidate keeps its gap there, less what a search looks for (its slack), and a later search
  // tests only the candidates whose slack is at most 2 drift: every other one would fail its tests anyway.
  struct StepCandidates {
    bool valid = false;
    VecX start, end;  // nxs and nxe they were found for
    double margin = 0;
    std::vector<std::pair<int, int>> vf, ee;
    std::vector<Closest> closest;  // at the start, per candidate (vf, then ee)
    // The candidates each search may test, with the drift up to which they need no test (each search then takes those
    // whose slack is at most 2 drift): those within the thickness at the start (repel); those apart at the start
    // whose gap at the end may come within the thickness (nearPairs); those whose distance may come within twice eta
    // along the step (detect). A candidate with slack above what any drift within the margin allows is left out.
    std::vector<int> near;
    std::vector<std::pair<int, double>> closing, hitting;
    // The smallest start distance over the candidates within the thickness there (near: repel's statistic).
    double near_min = std::numeric_limits<double>::infinity();
    // Per candidate, where nearPairs put its pair in out at this step (SIZE_MAX: nowhere yet).
    std::vector<std::size_t> joined;
    // How the list was found: the frames and padding of its boxes, swept from start to end (a list the step skin
    // served is cut down to such a broad phase's, in the world's frame). updateStep brings it to a new end.
    Frames frames;
    // findStep's per-candidate values before they are sorted into the lists above.
    struct {
      std::vector<double> closing, hitting;
      std::vector<char> near;
    } scratch;
  } step;
  // The round's nearest points at the start, per candidate (a NaN distance: not found), found by repel for the
  // continuous test that follows it on the same lists (detect): valid until the next broad phase.
  std::vector<Closest> round_closest;
  bool round_closest_valid = false;
  bool from_step = false;   // the candidates are step's (vf and ee are not used)
  double drift = 0;         // with from_step: the largest distance of a node's end from step.end
  std::vector<int> subset;  // the candidates a search tests (subsetOf)
  ContactPairSet known;     // nearPairs: the pairs already in its list

  const std::vector<std::pair<int, int>>& vfList() const { return from_step ? step.vf : vf; }
  const std::vector<std::pair<int, int>>& eeList() const { return from_step ? step.ee : ee; }

  // Takes the step's candidates if they stand for (nxs, nxe), or can be brought to it (update: updateStep); returns
  // whether it did.
  bool reuseStep(bool update = true) {
    if (!motion_cull || !step.valid || step.start.size() != nxs.size() || step.end.size() != nxe.size()) return false;
    if (std::memcmp(step.start.data(), nxs.data(), sizeof(double) * std::size_t(nxs.size())) != 0) return false;
    if (!((nxe - step.end).cwiseAbs().maxCoeff() <= step.margin) && !(update && updateStep())) return false;
    from_step = true;
    drift = 0;
    for (int k = 0; k < nodeCount(); ++k) drift = std::max(drift, (particle(nxe, k) - particle(step.end, k)).norm());
    return true;
  }
  // The candidates of a later round of the pass, after impulses changed some trajectories (dirty nodes): the step's
  // list where it stands for the new ends as it is (each within the margin of the end it was found for: detect then
  // tests its candidates with a dirty node), else a broad phase of the elements holding a dirty node. Never the step's
  // list brought up to date: impulses may move many nodes a little beyond the margin, and an update sorts the whole
  // list again, where the marked lookup touches only what moved. False: over the budget.
  bool laterRoundCandidates(Stats& stats) {
    if (reuseStep(false)) {
      ++stats.step_rounds;
      return true;
    }
    return broadPhase(true);
  }
  // Whether coordinate j of the nodes, swept over the step (nxs to nxe), lies within [lo[j], hi[j]].
  bool sweptWithin(const VecX& lo, const VecX& hi, Eigen::Index j) const {
    return std::min(nxs[j], nxe[j]) >= lo[j] && std::max(nxs[j], nxe[j]) <= hi[j];
  }
  // Candidates kept across steps, as a Verlet list keeps its neighbours within a skin: found for boxes padded by a
  // margin (kSkinFraction of the largest thickness) more than a broad phase needs, they hold every pair of that broad
  // phase for any step whose nodes all lie, at its start and its end, within half that margin of the box each swept
  // when they were found (the other half covers the rounding of the boxes): each padded box the step needs then lies
  // inside the skin's. The surplus pairs, in the same ascending order, fail the geometric tests that follow (start
  // boxes within the thickness, an axis apart all along, a hit, a gap): the same contacts in the same order. Serves
  // steps that move a node by a small part of the thickness (an explicit integrator's; a body resting under backward
  // Euler), where the broad phase is much of the work; a skin is built only after such a step. This one is the pass's
  // (the exact broad phase's pairs; backward Euler's step lists keep theirs up to date in part, StepSkin).
  // The pass's also keeps a lower bound of each candidate's distance at the start of the step that found the list
  // (its nearest points' distance where repulsion found them, else its start boxes' gap along an axis). Moving each
  // node by at most D from there changes the distance between two elements by at most 2 D (each element's hull moves
  // by at most D), and along a linear step each node stays within the larger of its two ends' displacements. So a
  // later step skips, in repulsion, the candidates whose bound less 2 D stays above the thickness and the smallest
  // distance seen (they neither touch nor lower it), and in continuous detection those whose bound less 2 D stays
  // above twice eta: the same contacts, hits and statistics.
  struct Skin {
    bool valid = false;
    VecX lo, hi;  // per node coordinate: where the node may lie at a step's start and end
    std::vector<std::pair<int, int>> vf, ee;
    VecX reference;             // the nodes' start when the list was found
    std::vector<double> lower;  // the pass's, per candidate: a lower bound of its distance there
    bool lower_valid = false;   // filled by the repulsion of the step that found the list
    int served = 1;             // steps the last list found served (before any: taken as served)
  } skin;
  bool from_skin = false;  // the round's candidates are the pass's skin's (vf, ee copied from it)
  // The largest distance of a node from the skin's reference, over the given per-node vectors.
  double skinDrift(std::initializer_list<const VecX*> xs) const {
    double most = 0;
    for (const VecX* x : xs)
      for (int k = 0; k < nodeCount(); ++k)
        most = std::max(most, (particle(*x, k) - particle(skin.reference, k)).norm());
    return most;
  }
  // vf and ee for (nxs, nxe) from a broad phase padded by `margin` more than the exact one: k's list when it serves
  // (returns 1), else a new list for k when the step moved every node by less than half k's margin (then it likely
  // serves a step or more; returns 2), else the broad phase's (3). 0: over the budget. After a list that served no
  // step, the next is found only after a step that moved every node by less than a quarter of the margin: a list costs
  // more to find than the exact one (twice the candidates on a collapsed cloth), and a body whose every step moves
  // some node by a third to a half of the margin or more (a cloth settling onto itself) otherwise finds one nearly
  // every step and leaves it the next.
  int keptCandidates(Skin& k, double margin) {
    const double skin_margin = kSkinFraction * max_thickness;
    if (motion_cull && k.valid && k.lo.size() == nxs.size()) {
      bool inside = true;
      for (Eigen::Index j = 0; j < nxs.size() && inside; ++j) inside = sweptWithin(k.lo, k.hi, j);
      if (inside) {
        newCandidates();
        vf = k.vf;
        ee = k.ee;
        ++k.served;
        return 1;
      }
    }
    k.valid = false;
    if (motion_cull && (nxe - nxs).cwiseAbs().maxCoeff() < skin_margin / (k.served > 0 ? 2 : 4) &&
        broadPhase(false, margin + skin_margin, true)) {
      k.lo = nxs.cwiseMin(nxe).array() - skin_margin / 2;
      k.hi = nxs.cwiseMax(nxe).array() + skin_margin / 2;
      k.vf = vf;
      k.ee = ee;
      k.reference = nxs;
      k.valid = true;
      k.served = 0;
      ++counters->skin_lists;
      return 2;
    }
    return broadPhase(false, margin) ? 3 : 0;
  }
  // Backward Euler's step lists kept across steps, as a Verlet list kept up to date in part (the pass's Skin is kept
  // whole or not at all): each node has an interval per coordinate, its start and end when it was set widened by
  // kNodeSlackFraction of the largest thickness each way; each element a box (and diagonals) over its nodes'
  // intervals, padded as the step's boxes are; and the list holds every pair whose boxes overlap (found as a broad
  // phase finds them). At a step whose nodes all lie, at its start and its end, within their intervals, each element's
  // box for the step (in the world's frame) lies inside its kept one (rounding is monotone: the same sums of smaller
  // numbers are no larger), so every pair of that step's broad phase is in the list, and testing each listed pair's
  // boxes and diagonals for the step cuts the list down to exactly that broad phase's pairs, in the same order, with no
  // lookup. A node outside its interval gets a new one, and only the elements holding such a node are looked up again
  // (their kept pairs dropped, their new ones merged in order): on a cloth lying collapsed on itself 4 to 8% of the
  // nodes a step, where a whole broad phase was the largest part of detection (docs/body-contact.md).
  struct StepSkin {
    bool valid = false;
    VecX lo, hi;  // per node coordinate
    ElementBoxes boxes;
    std::vector<std::pair<int, int>> vf, ee;
    std::vector<char> outside;  // per node: outside its interval at this step
    std::vector<std::pair<int, int>> fresh_vf, fresh_ee, merged;
  } step_skin;
  // The box and diagonals of an element over its nodes' step skin intervals, padded (fillBoxes).
  auto stepSkinBox(double pad) const {
    return [this, pad](const auto& nodes, int, Box& box_out, Diagonals& diagonals_out) {
      const StepSkin& k = step_skin;
      box_out = Box{Vec3::Constant(std::numeric_limits<double>::infinity()),
                    Vec3::Constant(-std::numeric_limits<double>::infinity())};
      diagonals_out = Diagonals{};
      for (const int i : nodes) {
        const Vec3 lo = particle(k.lo, i), hi = particle(k.hi, i);
        box_out.lo = box_out.lo.cwiseMin(lo);
        box_out.hi = box_out.hi.cwiseMax(hi);
        diagonals_out.include(lo, hi);
      }
      box_out.lo.array() -= pad;
      box_out.hi.array() -= -pad;
      for (int j = 0; j < 6; ++j) diagonals_out.lo[j] -= 2 * pad, diagonals_out.hi[j] += 2 * pad;
    };
  }
  // Into vf and ee, the pairs of a broad phase over (nxs, nxe) in the world's frame with boxes padded by pad, from the
  // step skin: 1 when it served (brought up to date or not), 2 when it was found anew; 0 when it cannot serve this
  // step (the caller then runs the broad phase): more than a quarter of the nodes left their intervals, or it is not
  // found anew after a step that moved more than an eighth of the nodes by more than their slack (most of a falling
  // body's: they would leave at the next step), or it would exceed the candidate budget.
  int stepSkinCandidates(double pad) {
    StepSkin& k = step_skin;
    if (!motion_cull) return k.valid = false, 0;  // the exact broad phase every time
    newCandidates();
    const int n = nodeCount();
    if (k.lo.size() != nxs.size()) k.valid = false;
    const double slack = kNodeSlackFraction * max_thickness;
    int result = 1;
    if (k.valid) {
      k.outside.assign(n, 0);
      int count = 0;
      for (int i = 0; i < n; ++i) {
        bool inside = true;
        for (int j = 3 * i; j < 3 * i + 3; ++j) inside = inside && sweptWithin(k.lo, k.hi, j);
        k.outside[i] = !inside;
        count += !inside;
      }
      k.valid = count <= n / 4 && (count == 0 || updateStepSkin(pad, slack));
    }
    if (!k.valid) {
      int fast = 0;
      for (int i = 0; i < n; ++i) fast += !((particle(nxe, i) - particle(nxs, i)).cwiseAbs().maxCoeff() <= slack);
      if (fast > n / 8) return 0;
      k.lo = nxs.cwiseMin(nxe).array() - slack;
      k.hi = nxs.cwiseMax(nxe).array() + slack;
      fillBoxes(k.boxes, false, stepSkinBox(pad));
      if (!findPairs(
              k.boxes, [&](int a, int b) { return bodiesMeet(a, b); }, false, false, k.vf, k.ee, 0))
        return 0;
      ++counters->broad_phases;
      counters->candidates += long(k.vf.size() + k.ee.size());
      ++counters->skin_lists;
      k.valid = true;
      result = 2;
    }
    // The skin's pairs whose boxes and diagonals for this step meet.
    listed.pad = pad;
    listed.shifts.clear();
    fillSweptBoxes(nxe, nullptr, pad);
    keepPairs(k.vf, vf, [&](int v, int t) {
      return boxes.vertex[v].overlaps(boxes.triangle[t]) &&
             !diagonallyApart(boxes.vertex_diagonals[v], boxes.triangle_diagonals[t]);
    });
    keepPairs(k.ee, ee, [&](int e, int f) {
      return boxes.edge[e].overlaps(boxes.edge[f]) &&
             !diagonallyApart(boxes.edge_diagonals[e], boxes.edge_diagonals[f]);
    });
    return result;
  }
  // The step skin's nodes marked outside get new intervals, and the pairs of the elements holding one are found
  // again. False: over the budget.
  bool updateStepSkin(double pad, double slack) {
    StepSkin& k = step_skin;
    for (int i = 0; i < nodeCount(); ++i)
      if (k.outside[i])
        for (int j = 3 * i; j < 3 * i + 3; ++j)
          k.lo[j] = std::min(nxs[j], nxe[j]) - slack, k.hi[j] = std::max(nxs[j], nxe[j]) + slack;
    markElements(k.outside);
    fillBoxes(k.boxes, true, stepSkinBox(pad));
    if (!findPairs(
            k.boxes, [&](int a, int b) { return bodiesMeet(a, b); }, true, false, k.fresh_vf, k.fresh_ee, 0))
      return false;
    ++counters->broad_phases;
    ++counters->skin_updates;
    counters->candidates += long(k.fresh_vf.size() + k.fresh_ee.size());
    mergeUnmarked(k.vf, k.fresh_vf, vertex_moved, triangle_moved, k.merged);
    k.vf.swap(k.merged);
    mergeUnmarked(k.ee, k.fresh_ee, edge_moved, edge_moved, k.merged);
    k.ee.swap(k.merged);
    return k.vf.size() + k.ee.size() <= candidateBudget();
  }
  std::vector<char> keep_scratch;  // keepPairs', kept from step to step
  // The pairs of `in` for which keep(first, second) holds, into out in order (on threads).
  template <class Keep>
  void keepPairs(const std::vector<std::pair<int, int>>& in, std::vector<std::pair<int, int>>& out, Keep&& keep) {
    const int n = int(in.size()), chunk = particleChunk(n), chunks = (n + chunk - 1) / chunk;
    std::vector<int> count(chunks + 1, 0);
    std::vector<char>& kept = keep_scratch;  // per pair
    kept.resize(n);
    forEachChunk(n, parallel, [&](int begin, int end) {
      int c = 0;
      for (int j = begin; j < end; ++j) c += kept[j] = keep(in[j].first, in[j].second);
      count[begin / chunk + 1] = c;
    });
    for (int c = 0; c < chunks; ++c) count[c + 1] += count[c];
    out.resize(count[chunks]);
    forEachChunk(n, parallel, [&](int begin, int end) {
      int at = count[begin / chunk];
      for (int j = begin; j < end; ++j)
        if (kept[j]) out[at++] = in[j];
    });
  }

  // The candidates for the pass over (nxs, nxe) (keptCandidates). False: over the budget.
  bool passCandidates(Stats& stats) {
    const int found = keptCandidates(skin, 0);
    if (found == 1) {
      from_skin = true;
      ++stats.skin_passes;
    } else if (found == 2) {
      from_skin = true;
      skin.lower.assign(vf.size() + ee.size(), 0.0);
      skin.lower_valid = false;
    }
    return found != 0;
  }

  // The step's candidates for (nxs, nxe), found anew, with their nearest points at the start and gaps at the end.
  // Returns false (no candidates: the step stays invalid) when the broad phase exceeds its budget.
  bool findStep(Stats& stats) {
    step.margin = kStepMarginFraction * max_thickness;
    step.valid = false;
    int found = stepSkinCandidates(0.5 * max_thickness + step.margin);
    if (!found) found = broadPhase(false, step.margin) ? 3 : 0;
    if (!found) return false;
    stats.skin_searches += found == 1;
    step.frames = listed;
    step.start = nxs;
    step.end = nxe;
    step.vf.swap(vf);
    step.ee.swap(ee);
    from_step = true;
    drift = 0;
    const int n = pairCount();
    step.joined.assign(n, SIZE_MAX);
    step.closest.resize(n);
    auto& [closing, hitting, near] = step.scratch;  // kept: fresh pages each step cost more than the work
    closing.resize(n), hitting.resize(n), near.resize(n);
    forEachChunk(n, parallel, [&](int begin, int end) {
      for (int k = begin; k < end; ++k) measureStep(k);
    });
    step.near_min = std::numeric_limits<double>::infinity();
    sortStep();
    step.valid = true;
    return true;
  }
  // Candidate k of the step's lists: its nearest points at the start, and the values sortStep sorts it by, at the
  // nodes' ends step.end.
  void measureStep(int k) {
    auto& [closing, hitting, near] = step.scratch;
    const PairInfo p = pairInfo(k);
    const auto x = points(nxs, p.stencil);
    const Closest c = nearest(p.kind, x);
    step.closest[k] = c;
    double gap = -std::numeric_limits<double>::infinity();  // at the end along the start's direction
    if (c.distance > 0) {
      const double end_gap = gapAlong(c.delta / c.distance, step.end, p.stencil.vertex, p.first());
      if (std::isfinite(end_gap)) gap = end_gap;
    }
    const double eta2 = 2 * kEtaFraction * p.thickness;
    closing[k] = c.distance > 0 ? gap - (1 + 1e-5) * p.thickness : std::numeric_limits<double>::infinity();
    hitting[k] = c.distance > eta2 ? gap - eta2 : -std::numeric_limits<double>::infinity();
    near[k] = c.distance < p.thickness;
  }
  // The step's lists (StepCandidates) from its candidates' measures, and near_min lowered by theirs. Only the
  // candidates in a list stay (in order, their measures with them): any other can pass no test at an end the list
  // serves, and is measured again only if updateStep finds it again.
  void sortStep() {
    // Any end the candidates serve lies within the margin of step.end along each axis: within sqrt(3) margin.
    const double most = 2 * std::sqrt(3.0) * step.margin;
    auto& [closing, hitting, near] = step.scratch;
    step.near.clear();
    step.closing.clear();
    step.hitting.clear();
    const int n = pairCount(), vf_count = int(step.vf.size());
    int kept = 0, kept_vf = 0;
    for (int k = 0; k < n; ++k) {
      if (!near[k] && closing[k] > most && hitting[k] > most) continue;
      const int j = kept++;
      if (k < vf_count) step.vf[kept_vf++] = step.vf[k];
      else step.ee[j - kept_vf] = step.ee[k - vf_count];
      step.closest[j] = step.closest[k], step.joined[j] = step.joined[k];
      closing[j] = closing[k], hitting[j] = hitting[k], near[j] = near[k];
      if (near[j]) step.near.push_back(j), step.near_min = std::min(step.near_min, step.closest[j].distance);
      if (!(closing[j] > most)) step.closing.emplace_back(j, closing[j]);
      if (!(hitting[j] > most)) step.hitting.emplace_back(j, hitting[j]);
    }
    step.ee.resize(kept - kept_vf), step.vf.resize(kept_vf);
    step.closest.resize(kept), step.joined.resize(kept);
    closing.resize(kept), hitting.resize(kept), near.resize(kept);
  }
  struct {
    std::vector<char> beyond;
    std::vector<std::pair<int, int>> fresh_vf, fresh_ee, merged_vf, merged_ee;
    std::vector<int> from;
    std::vector<Closest> closest;
    std::vector<double> old_closing, old_hitting;
    std::vector<char> old_near;
    std::vector<std::size_t> joined;
  } update_scratch;  // updateStep's, kept from step to step
  // Brings the step's own list (found by a broad phase for this start) to the end nxe when some nodes' ends lie beyond
  // the margin of those it was found for (a later solve of backward Euler's that moved part of the body far: an
  // impact): each such node's reference end becomes its new end; the candidates with no such node keep their place,
  // nearest points and measures (their boxes did not change); those with one are listed again, for their new boxes in
  // the list's frames, measured and sorted (sortStep). The list then holds, in the same order, what sortStep would keep
  // of a broad phase of the same frames and padding for the new reference ends; and every node's end lies within the
  // margin of its reference, as reuseStep asks. Returns false (the list is left as it was) when it would exceed the
  // candidate budget.
  bool updateStep() {
    auto& [beyond, fresh_vf, fresh_ee, merged_vf, merged_ee, from, closest, old_closing, old_hitting, old_near,
           joined] = update_scratch;
    beyond.assign(nodeCount(), 0);
    for (int k = 0; k < nodeCount(); ++k)
      beyond[k] = !((particle(nxe, k) - particle(step.end, k)).cwiseAbs().maxCoeff() <= step.margin);
    markElements(beyond);
    VecX end = step.end;
    for (int k = 0; k < nodeCount(); ++k)
      if (beyond[k]) particle(end, k) = particle(nxe, k);
    if (!listPairs(end, step.frames.shifts, step.frames.pad, true, false, fresh_vf, fresh_ee)) return false;
    // The kept candidates (no marked element) and the fresh ones, merged in order; per merged candidate its old index
    // (-1: fresh).
    from.clear();
    mergeUnmarked(step.vf, fresh_vf, vertex_moved, triangle_moved, merged_vf, &from, 0);
    mergeUnmarked(step.ee, fresh_ee, edge_moved, edge_moved, merged_ee, &from, int(step.vf.size()));
    if (merged_vf.size() + merged_ee.size() > candidateBudget()) return false;
    const int n = int(from.size());
    auto& [closing, hitting, near] = step.scratch;
    // The old measures copied aside (the kept list is short: sortStep keeps what a search may test), the step's
    // arrays refilled in place (they keep the room of the step's first, full list).
    closest.assign(step.closest.begin(), step.closest.end()), joined.assign(step.joined.begin(), step.joined.end());
    old_closing.assign(closing.begin(), closing.end());
    old_hitting.assign(hitting.begin(), hitting.end()), old_near.assign(near.begin(), near.end());
    step.vf.swap(merged_vf), step.ee.swap(merged_ee), step.end.swap(end);
    from_step = true;  // pairInfo reads the step's lists
    step.closest.resize(n), step.joined.resize(n);
    closing.resize(n), hitting.resize(n), near.resize(n);
    forEachChunk(n, parallel, [&](int begin, int stop) {
      for (int k = begin; k < stop; ++k) {
        const int i = from[k];
        if (i < 0) {
          step.joined[k] = SIZE_MAX;
          measureStep(k);
          continue;
        }
        step.closest[k] = closest[i], step.joined[k] = joined[i];
        closing[k] = old_closing[i], hitting[k] = old_hitting[i], near[k] = old_near[i];
      }
    });
    sortStep();
    ++counters->step_updates;
    return true;
  }
  // The pairs of old with neither element marked (first_marked, second_marked) and the fresh ones, merged in order into
  // out; per pair of out, appended to from when given, its index in old plus offset (-1: fresh).
  static void mergeUnmarked(const std::vector<std::pair<int, int>>& old, const std::vector<std::pair<int, int>>& fresh,
                            const std::vector<char>& first_marked, const std::vector<char>& second_marked,
                            std::vector<std::pair<int, int>>& out, std::vector<int>* from = nullptr, int offset = 0) {
    out.clear();
    std::size_t j = 0;
    const auto add_fresh = [&] {
      out.push_back(fresh[j++]);
      if (from) from->push_back(-1);
    };
    for (std::size_t i = 0; i < old.size(); ++i) {
      if (first_marked[old[i].first] || second_marked[old[i].second]) continue;
      while (j < fresh.size() && fresh[j] < old[i]) add_fresh();
      out.push_back(old[i]);
      if (from) from->push_back(offset + int(i));
    }
    while (j < fresh.size()) add_fresh();
  }
  // The nearest points at the start of candidate k (whose stencil's start points are x), from the step's when known.
  Closest startClosest(int k, Primitive kind, const std::array<Vec3, 4>& x) const {
    if (from_step) return step.closest[k];
    return nearest(kind, x);
  }
  // The largest gap along an axis between the start's boxes of the pair's elements (the swept ones found it): at
  // most the distance between the elements.
  static double startBoxGap(const PairInfo& p, const std::array<Vec3, 4>& x) {
    Vec3 lo0 = x[0].cwiseMin(x[1]), hi0 = x[0].cwiseMax(x[1]), lo1 = x[2].cwiseMin(x[3]), hi1 = x[2].cwiseMax(x[3]);
    if (p.kind == Primitive::PointTriangle) {
      lo0 = hi0 = x[0];
      lo1 = x[1].cwiseMin(lo1);
      hi1 = x[1].cwiseMax(hi1);
    }
    return std::max((lo0.array() - hi1.array()).maxCoeff(), (lo1.array() - hi0.array()).maxCoeff());
  }
  // With the step's candidates: those of a list (StepCandidates) whose slack is at most 2 drift, ascending; nullptr
  // (every candidate) otherwise.
  const std::vector<int>* subsetOf(const std::vector<std::pair<int, double>>& list) {
    if (!from_step) return nullptr;
    subset.clear();
    for (const auto& [k, slack] : list)
      if (!(slack > 2 * drift)) subset.push_back(k);
    return &subset;
  }

  int pairCount() const { return int(vfList().size() + eeList().size()); }
  // Candidate k's kind and its two elements (vf, then ee).
  std::tuple<Primitive, int, int> candidate(int k) const {
    const auto &v = vfList(), &e = eeList();
    return k < int(v.size()) ? std::tuple{Primitive::PointTriangle, v[k].first, v[k].second}
                             : std::tuple{Primitive::EdgeEdge, e[k - v.size()].first, e[k - v.size()].second};
  }
  PairInfo pairInfo(int k) const {
    const auto [kind, first, second] = candidate(k);
    return info(kind, first, second);
  }
  // The stencil's vertices of candidate k (PairInfo's, without the rest).
  std::array<int, 4> pairNodes(int k) const {
    const auto [kind, first, second] = candidate(k);
    return nodes(kind, first, second);
  }

  // fn(k, info) over every candidate pair k (or those in only, ascending) on threads in fixed chunks; what it returns
  // (an optional) is gathered in pair order. With counted, fn(k, info, count) may also count, each chunk on its own,
  // and *counted is the sum.
  template <class Fn>
  auto gather(Fn&& fn, const std::vector<int>* only = nullptr, std::size_t* counted = nullptr) {
    constexpr bool counts = std::is_invocable_v<Fn&, int, const PairInfo&, std::size_t&>;
    using Found = typename std::conditional_t<counts, std::invoke_result<Fn&, int, const PairInfo&, std::size_t&>,
                                              std::invoke_result<Fn&, int, const PairInfo&>>::type::value_type;
    const int n = only ? int(only->size()) : pairCount();
    const int chunk = 1024, chunks = (n + chunk - 1) / chunk;
    std::vector<std::vector<Found>> parts(chunks);
    std::vector<std::size_t> count(chunks, 0);
    const auto run = [&](int c) {
      for (int j = c * chunk; j < std::min(n, (c + 1) * chunk); ++j) {
        const int k = only ? (*only)[j] : j;
        if constexpr (counts) {
          if (auto found = fn(k, pairInfo(k), count[c])) parts[c].push_back(*found);
        } else if (auto found = fn(k, pairInfo(k))) {
          parts[c].push_back(*found);
        }
      }
    };
    if (parallel && chunks > 1)
      tbb::parallel_for(tbb::blocked_range<int>(0, chunks, 1), [&](const tbb::blocked_range<int>& r) {
        for (int c = r.begin(); c != r.end(); ++c) run(c);
      });
    else
      for (int c = 0; c < chunks; ++c) run(c);
    std::vector<Found> out;
    for (const auto& part : parts) out.insert(out.end(), part.begin(), part.end());
    if (counted) *counted = std::accumulate(count.begin(), count.end(), std::size_t(0));
    return out;
  }

  // The stencil's vertices in a per-node vector (nxs, nxe).
  std::array<Vec3, 4> points(const VecX& x, const Stencil& s) const {
    return {particle(x, s.vertex[0]), particle(x, s.vertex[1]), particle(x, s.vertex[2]), particle(x, s.vertex[3])};
  }

  Vec3 relativeVelocity(const Stencil& s, const std::array<double, 4>& w) const {
    Vec3 u = Vec3::Zero();
    for (int i = 0; i < 4; ++i) u += w[i] * particle(nvbar, s.vertex[i]);
    return u;
  }

  // Changes the relative velocity sum w_i vbar_i by dv, split by the weights and inverse masses over the vertices'
  // particles (an impulse along the pair's stencil of particles: the vertices' own mass 1 / sum W^2 / m is in it).
  void applyImpulse(const Stencil& s, const std::array<double, 4>& w, const Vec3& dv, double h) {
    const WeightedStencil e = expand(s, w);
    const double denom = e.inverseMass(inv_mass);
    if (denom <= 0) return;
    std::array<int, WeightedStencil::kCapacity> moved;
    int count = 0;
    for (int i = 0; i < e.size; ++i) {
      const int p = e.particle[i];
      const double share = e.w[i] * inv_mass[p] / denom;
      if (share == 0) continue;
      particle(vbar, p) += share * dv;
      particle(xe, p) = particle(xs, p) + h * particle(vbar, p);
      changed[p] = 1;
      moved[count++] = p;
    }
    refreshNodes(std::span<const int>(moved.data(), count));
  }

  double weightNorm(const Stencil& s, const std::array<double, 4>& w) const {
    return expand(s, w).inverseMass(inv_mass);
  }

  // The normal of a pair whose nearest points at x are c: along them, or where they touch (no direction between
  // them) the triangle's or the edges'. Not finite for a degenerate touching pair.
  static Vec3 contactNormal(Primitive kind, const std::array<Vec3, 4>& x, const Closest& c) {
    if (c.distance > 0) return c.delta / c.distance;
    if (kind == Primitive::PointTriangle) return (x[2] - x[1]).cross(x[3] - x[1]).normalized();
    return (x[1] - x[0]).cross(x[3] - x[2]).normalized();
  }
  std::vector<long> contact_counts;  // repel's per chunk, kept from step to step
  // Step 1: repulsion and friction for pairs within the thickness at the start (only counted without impulses).
  void repel(double h, Stats& stats, bool impulses) {
    // With the step's candidates: those within the thickness at the start, their smallest distance known (near_min).
    const auto* only = from_step ? &step.near : nullptr;
    if (only) stats.min_distance = std::min(stats.min_distance, step.near_min);
    if (only && !impulses && !from_skin) {
      // Counting is all that is left (the pairs' distances are in near_min): the pairs the gather below would
      // return as contacts, counted per chunk, without gathering them.
      const std::vector<int>& near = *only;
      stats.contacts += sumOverChunks(int(near.size()), parallel, contact_counts, [&](int begin, int end) {
        long count = 0;
        for (int j = begin; j < end; ++j) {
          const int k = near[j];
          const PairInfo p = pairInfo(k);
          const auto x = points(nxs, p.stencil);
          const Closest& c = step.closest[k];
          if (startBoxGap(p, x) > p.thickness || !(c.distance < p.thickness)) continue;
          count += contactNormal(p.kind, x, c).allFinite();
        }
        return count;
      });
      round_closest_valid = false;
      return;
    }
    round_closest_valid = !from_step;
    if (round_closest_valid)
      round_closest.assign(pairCount(), Closest{std::numeric_limits<double>::quiet_NaN(), {}, Vec3::Zero()});
    // The skin's candidates: those its bounds keep apart are skipped (Skin), or the bounds are filled.
    const bool skip = from_skin && skin.lower_valid, fill = from_skin && !skin.lower_valid;
    const double moved = skip ? 2 * skinDrift({&nxs}) : 0, seen = stats.min_distance;
    const std::vector<Contact> near = gather(
        [&](int k, const PairInfo& p) -> std::optional<Contact> {
          if (skip && skin.lower[k] - moved > std::max(p.thickness, seen)) return std::nullopt;
          const auto x = points(nxs, p.stencil);
          // The start's boxes (the swept ones found the pair) further apart than the thickness: not near.
          const double box_gap = startBoxGap(p, x);
          if (box_gap > p.thickness) {
            if (fill) skin.lower[k] = box_gap;  // each k on one thread
            return std::nullopt;
          }
          const Closest c = startClosest(k, p.kind, x);
          if (fill) skin.lower[k] = c.distance;
          if (round_closest_valid) round_closest[k] = c;  // each k on one thread
          if (c.distance >= p.thickness) return std::nullopt;
          const Vec3 normal = contactNormal(p.kind, x, c);
          if (!normal.allFinite()) return Contact{k, c, Vec3::Zero(), -1};
          return Contact{k, c, normal, 0};
        },
        only);
    skin.lower_valid = skin.lower_valid || fill;
    for (const Contact& c : near) {
      stats.min_distance = std::min(stats.min_distance, c.at.distance);
      if (c.t < 0) continue;
      ++stats.contacts;
      if (!impulses) continue;
      const PairInfo p = pairInfo(c.pair);
      const double denom = weightNorm(p.stencil, c.at.w);
      if (denom <= 0) continue;
      const Vec3 u = relativeVelocity(p.stencil, c.at.w);
      const double un = c.normal.dot(u), gap = p.thickness - c.at.distance;
      // Inelastic: stop the approach. Repulsion: a spring of stiffness k over the gap left for one step, at most
      // enough to close a tenth of it within the step (Bridson 2002, 7.2).
      const double stop = std::max(0.0, -un), after = un + stop;
      const double spring = h * p.stiffness * gap * denom;
      const double repel = std::max(0.0, std::min(spring, kRepulsionFraction * gap / h - after));
      const double dn = stop + repel;
      if (dn <= 0) continue;
      Vec3 dv = dn * c.normal;
      const Vec3 ut = u - un * c.normal;
      const double speed = ut.norm();
      if (speed > 0) dv -= std::min(p.friction * dn / speed, 1.0) * ut;  // Coulomb: at most mu times the normal change
      applyImpulse(p.stencil, c.at.w, dv, h);
    }
  }

  // Continuous detection over the pairs with a particle moved since the last round (every pair when all is set).
  // Within zones: pairs inside one impact zone are skipped, as its motion x0 + s h (v + w x r) is an invertible
  // affine map of the zone for every s (det(I + s h [w]x) = 1 + s^2 h^2 |w|^2), which keeps four points off a plane.
  std::vector<Contact> detect(bool all, bool within_zones = false) {
    const auto inOneZone = [&](const Stencil& s) {
      const int r = root[node_particle[node_start[s.vertex[0]]]];
      for (const int k : s.vertex)
        for (int j = node_start[k]; j < node_start[k + 1]; ++j)
          if (root[node_particle[j]] != r) return false;
      return true;
    };
    if (within_zones)
      for (const int p : pass_particles) root[p] = zones.find(p);
    // With the step's candidates: those whose distance may come within eta along the step.
    const auto* only = subsetOf(step.hitting);
    // The skin's candidates: those its bounds keep further apart than twice eta all along the step are skipped.
    const bool skip = all && from_skin && skin.lower_valid;
    const double drifted = skip ? 2 * skinDrift({&nxs, &nxe}) : 0;
    std::vector<Contact> hits = gather(
        [&](int k, const PairInfo& p) -> std::optional<Contact> {
          if (skip && skin.lower[k] - drifted > 2 * kEtaFraction * p.thickness) return std::nullopt;
          if (!all) {
            bool moved = false;
            for (const int i : p.stencil.vertex) moved |= dirty[i] != 0;
            if (!moved) return std::nullopt;
          }
          if (within_zones && inOneZone(p.stencil)) return std::nullopt;
          const auto& q = p.stencil.vertex;
          const int first = p.first();
          // Two filters, the cheaper first (one direction where the nearest points at the start are known, else three
          // axes): the step's list carries them for every candidate, repulsion finds them for the round's first test.
          const Closest* start = from_step                    ? &step.closest[k]
                                 : all && round_closest_valid ? &round_closest[k]
                                                              : nullptr;
          if (cull && start && apartAlongNearest(*start, q, first, p.thickness)) return std::nullopt;
          if (apartAllStep(q.data(), first, q.data() + first, 4 - first, p.thickness)) return std::nullopt;
          const auto hit = firstHit(p.kind, points(nxs, p.stencil), points(nxe, p.stencil), kEtaFraction * p.thickness);
          if (!hit) return std::nullopt;
          return Contact{k, hit->at, hit->normal, hit->t};
        },
        only);
    std::fill(dirty.begin(), dirty.end(), 0);
    return hits;
  }

  void impulses(const std::vector<Contact>& hits, double h) {
    for (const Contact& c : hits) {
      const PairInfo p = pairInfo(c.pair);
      const double un = c.normal.dot(relativeVelocity(p.stencil, c.at.w));
      if (un >= 0) continue;  // an earlier impulse of this round already separated it
      const double left = std::max(1 - c.t, 1e-6) * h;
      const double target = std::min(kSeparation * -un, kEndGapFraction * p.thickness / left);
      applyImpulse(p.stencil, c.at.w, (target - un) * c.normal, h);
    }
  }

  // Step 3: merge the hits' particles into zones, and move every zone touched as a rigid body. Returns its size.
  int rigidify(const std::vector<Contact>& hits, double h) {
    std::vector<char> touched(inv_mass.size(), 0);
    for (const Contact& c : hits) {  // the particles of the pair's vertices
      const auto& s = pairInfo(c.pair).stencil;
      const int first = node_particle[node_start[s.vertex[0]]];
      for (const int k : s.vertex)
        for (int j = node_start[k]; j < node_start[k + 1]; ++j) {
          zones.merge(first, node_particle[j]);
          touched[node_particle[j]] = 1;
        }
    }
    // Every member of a touched zone: zones grow across rounds, so gather them from the roots.
    std::vector<char> root_touched(inv_mass.size(), 0);
    for (const int p : pass_particles)
      if (touched[p]) root_touched[zones.find(p)] = 1;
    std::vector<std::vector<int>> members(inv_mass.size());
    for (const int p : pass_particles)
      if (root_touched[zones.find(p)]) members[zones.find(p)].push_back(p);
    int largest = 0;
    for (const auto& zone : members) {
      if (zone.empty()) continue;
      largest = std::max(largest, int(zone.size()));
      bool pinned = false;
      double mass = 0;
      Vec3 center = Vec3::Zero(), momentum = Vec3::Zero();
      for (const int p : zone) {
        if (inv_mass[p] == 0) {
          pinned = true;
          continue;
        }
        const double m = 1 / inv_mass[p];
        mass += m;
        center += m * particle(xs, p);
        momentum += m * particle(vbar, p);
      }
      Vec3 velocity = Vec3::Zero(), omega = Vec3::Zero();
      if (!pinned) {
        center /= mass;
        velocity = momentum / mass;
        Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
        Vec3 angular = Vec3::Zero();
        for (const int p : zone) {
          const double m = 1 / inv_mass[p];
          const Vec3 r = particle(xs, p) - center;
          angular += m * r.cross(particle(vbar, p) - velocity);
          inertia += m * (r.squaredNorm() * Eigen::Matrix3d::Identity() - r * r.transpose());
        }
        omega = inertia.completeOrthogonalDecomposition().solve(angular);  // collinear zones: the least-norm spin
      }
      for (const int p : zone) {
        particle(vbar, p) = pinned ? Vec3::Zero() : Vec3(velocity + omega.cross(particle(xs, p) - center));
        particle(xe, p) = particle(xs, p) + h * particle(vbar, p);
        changed[p] = 1;
      }
      refreshNodes(zone);
    }
    return largest;
  }
};

BodyCollisions::BodyCollisions(const std::vector<Surface>& surfaces, const VecX& inverse_mass, Settings settings,
                               bool parallel)
    : impl_(std::make_unique<Impl>(surfaces, inverse_mass, settings, parallel)) {
  impl_->counters = &stats_;
}

BodyCollisions::~BodyCollisions() = default;

bool BodyCollisions::needed(const std::vector<Surface>& surfaces) {
  if (surfaces.size() > 1) return true;
  return !surfaces.empty() && surfaces[0].params.self_contact;
}

bool BodyCollisions::nearPairs(const VecX& x0, const VecX& x1, std::vector<ContactPair>& out, PairJoin& join) {
  Impl& s = *impl_;
  if (!x1.allFinite()) return false;
  s.blendNodes(x0, s.nxs);
  s.blendNodes(x1, s.nxe);
  // The shortcuts off: the exact broad phase, every time; so too when the step's list, padded by its margin, would be
  // over the candidate budget (the exact one may fit, and then the pass after the step goes on: the solve must have
  // its pairs). Over the budget even so: no pairs (the pass after the step stops the run).
  if (!motion_cull ? !s.broadPhase() : !s.reuseStep() && !s.findStep(stats_) && !s.broadPhase()) return false;
  // With the step's candidates: those apart at the start whose gap at x1 may be within the thickness.
  const auto* only = s.subsetOf(s.step.closing);
  const std::size_t before = out.size();
  s.known.assign(out);  // the pairs already in out
  // A candidate whose pair an earlier search of this step put in out (the same list of candidates), and which is
  // still there, is in out: it leaves the subset before its tests and the set's lookup, as the lookup would drop it.
  // (A step's later searches find the pairs the earlier ones handed over so.)
  if (only) {
    const auto still_in_out = [&](int k) {
      const std::size_t at = s.step.joined[k];
      return at < before && ContactPairSet::same(out[at].element, s.pairNodes(k));
    };
    s.subset.erase(std::remove_if(s.subset.begin(), s.subset.end(), still_in_out), s.subset.end());
  }
  // Each candidate on threads (gather keeps the pair order): its nearest points at x0, then its gap at x1. What
  // joins is gathered small (the candidate, its weights and normal) and expanded into out after: a pair is 152 bytes
  // (472 when its stencil held room for 32 particles in place, and copying tens of thousands of them through
  // temporaries cost more than the tests).
  struct Joining {
    int k;
    std::array<double, 4> w;
    Vec3 normal;
  };
  const std::vector<Joining> found = s.gather(
      [&](int k, const PairInfo& p, std::size_t& held_back) -> std::optional<Joining> {
        const auto x = s.points(s.nxs, p.stencil);
        const Closest c = s.startClosest(k, p.kind, x);
        if (!(c.distance > 0)) return std::nullopt;  // touching at the start: no direction (the post-step pass has it)
        const Vec3 normal = c.delta / c.distance;
        // The gap at x1 from the nodes first (cheap, and most candidates are far from closing); the pair's own, over
        // its particles, decides (it differs in rounding only, far below this margin).
        Vec3 end_relative = Vec3::Zero();
        for (int i = 0; i < 4; ++i) end_relative += c.w[i] * particle(s.nxe, p.stencil.vertex[i]);
        const double node_gap = normal.dot(end_relative) - p.thickness;
        if (node_gap > 1e-6 * p.thickness) return std::nullopt;
        if (before > 0 && s.known.contains(p.stencil.vertex)) return std::nullopt;  // (an empty out holds none)
        // Where every node is one particle of weight 1 the pair's own gap is the nodes' to the bit (the same particles,
        // weights and sums): no pair built to find it.
        const double gap =
            s.single_particle_nodes
                ? node_gap
                : ContactPair{p.stencil.vertex, s.expand(p.stencil, c.w), normal, p.thickness, p.friction}.gap(x1);
        if (!(gap < 0)) return std::nullopt;
        // The linearized gap of a pair far apart at x0 says little: only a pair that does come within the thickness at
        // x1 (or crosses on the way) joins. The start's nearest points are points of the elements at x1 too, so the
        // elements are no further apart there than end_relative is long: within the thickness (less a hair, for the
        // rounding of the exact test it spares), they are (97 in 100 of the pairs tested here on a cloth lying on
        // itself).
        if (!(end_relative.squaredNorm() < (1 - 1e-9) * (1 - 1e-9) * p.thickness * p.thickness)) {
          const auto e = s.points(s.nxe, p.stencil);
          const Closest end = nearest(p.kind, e);
          if (!(end.distance < p.thickness) && !firstHit(p.kind, x, e, kEtaFraction * p.thickness)) return std::nullopt;
        }
        if (!join.hands(p.stencil.vertex, c.distance - p.thickness, gap, p.thickness)) {
          ++held_back;
          return std::nullopt;
        }
        return Joining{k, c.w, normal};
      },
      only, &join.held_back);
  out.resize(before + found.size());
  forEachChunk(int(found.size()), s.parallel, [&](int begin, int end) {
    for (int j = begin; j < end; ++j) {
      if (only) s.step.joined[found[j].k] = before + j;
      const PairInfo p = s.pairInfo(found[j].k);
      out[before + j] =
          ContactPair{p.stencil.vertex, s.expand(p.stencil, found[j].w), found[j].normal, p.thickness, p.friction};
    }
  });
  return out.size() > before;
}

std::optional<Failure> BodyCollisions::resolve(const VecX& x0, VecX& x1, VecX& v1, double h, bool repulsion) {
  Impl& s = *impl_;
  if (!x1.allFinite() || !v1.allFinite()) return std::nullopt;  // a blow-up: Simulation reports it next
  ++stats_.passes;
  const Eigen::Index n = x0.size();
  s.xs = x0;
  s.xe = x1;
  s.vbar = (x1 - x0) / h;
  s.vbar0 = s.vbar;
  s.blendNodes(x0, s.nxs);
  s.blendNodes(x1, s.nxe);
  s.blendNodes(s.vbar, s.nvbar);
  s.changed.assign(n / 3, 0);
  s.dirty.assign(s.nodeCount(), 0);
  s.root.resize(n / 3);
  if (!s.reuseStep() && !s.passCandidates(stats_)) return s.overwhelmedFailure();  // an implicit solve's, or the pass's
  s.repel(h, stats_, repulsion);

  std::optional<Failure> failure;
  bool all = true, clean = false;  // the first detection tests every pair: repulsion moved only some
  std::vector<Contact> hits;
  for (int round = 0; round < s.settings.ccd_iterations; ++round) {
    if (round > 0 && !s.laterRoundCandidates(stats_)) return s.overwhelmedFailure();
    hits = s.detect(all);
    all = false;
    if (hits.empty()) {
      clean = true;
      break;
    }
    stats_.ccd_hits += long(hits.size());
    s.impulses(hits, h);
  }
  if (!clean) {  // the last round's impulses are not checked yet
    if (all ? !s.broadPhase() : !s.laterRoundCandidates(stats_)) return s.overwhelmedFailure();
    hits = s.detect(all);
  }
  if (!hits.empty()) {
    ++stats_.zone_activations;
    s.zones.reset(int(n / 3));
    int round = 0;
    for (; round < s.settings.zone_iterations && !hits.empty(); ++round) {
      stats_.largest_zone = std::max(stats_.largest_zone, s.rigidify(hits, h));
      ++stats_.zone_rounds;
      if (!s.broadPhase(true)) return s.overwhelmedFailure();
      hits = s.detect(false, true);
    }
    if (!hits.empty()) {
      const PairInfo p = s.pairInfo(hits[0].pair);
      std::ostringstream why;
      std::array<int, 4> q;  // each vertex by its particle (of an embedded point: the one of largest weight)
      for (int i = 0; i < 4; ++i) q[i] = s.mainParticle(p.stencil.vertex[i]);
      why << hits.size() << (hits.size() > 1 ? " collisions" : " collision") << " between body surfaces left after "
          << round << (round > 1 ? " rounds" : " round") << " of rigid impact zones (the first: ";
      if (p.kind == Primitive::PointTriangle)
        why << "particle " << q[0] << " against the triangle of particles " << q[1] << ", " << q[2] << ", " << q[3];
      else
        why << "the edge of particles " << q[0] << " and " << q[1] << " against the edge of particles " << q[2]
            << " and " << q[3];
      why << " at " << hits[0].t << " of the step)";
      failure = Failure{q[0], why.str()};
    }
  }
  for (Eigen::Index i = 0; i < n / 3; ++i)
    if (s.changed[i]) {
      particle(x1, i) = particle(s.xe, i);
      particle(v1, i) += particle(s.vbar, i) - particle(s.vbar0, i);
    }
  return failure;
}

}  // namespace wobble::collision
