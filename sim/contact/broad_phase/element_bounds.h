// The bounds of the surface elements (vertices, edges, triangles over nodes: surface_nodes.h) that the broad phase
// overlaps: each element's box swept over the step, padded, and its extents along the six diagonals of the box's axes.
// Box and diagonals make an 18-DOP (Klosowski et al. 1998, "Efficient collision detection using bounding volume
// hierarchies of k-DOPs"; for cloth, Mezger, Kimmerle & Etzmuss 2003, "Hierarchical techniques in collision detection
// for cloth animation"). On a cloth the boxes of a diagonal edge and of a triangle cover a whole cell, and reach its
// corner vertices and the edges there, some 0.7 spacings away: the diagonals drop those pairs.
#pragma once
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "sim/contact/broad_phase/broad_phase.h"
#include "sim/contact/surface_nodes.h"
#include "sim/solver/parallel.h"

namespace wobble::collision {

// Extents along the six diagonals of a box's axes, x + y, x - y, y + z, y - z, z + x, z - x.
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

// Per element, whether a node of it is marked (mark).
struct ElementMarks {
  std::vector<char> vertex, edge, triangle;
  void mark(const SurfaceNodes& nodes, const std::vector<char>& node_marks) {
    const auto each = [&](const auto& items, std::vector<char>& moved) {
      moved.resize(items.size());
      for (std::size_t k = 0; k < items.size(); ++k) {
        moved[k] = 0;
        for (const int p : items[k]) moved[k] |= node_marks[p];
      }
    };
    each(nodes.single_nodes, vertex);
    each(nodes.edges, edge);
    each(nodes.triangles, triangle);
  }
};

// The extents along the six diagonals of what a box (below) bounds, the points' swept hull from start to end_x (in a
// frame that moves by `shift` over the step) grown by a cube of half-side pad: each of the points' own, grown by 2 pad
// (the cube's reach along a diagonal). Two elements whose padded hulls meet overlap along every diagonal, as along
// every axis; where their boxes overlap but a diagonal parts them, they do not meet.
template <class Points>
Diagonals sweptDiagonals(const Points& points, double pad, const VecX& start, const VecX& end_x, const Vec3& shift) {
  Diagonals out;
  for (const int i : points) out.include(particle(start, i)), out.include(particle(end_x, i) - shift);
  for (int k = 0; k < 6; ++k) out.lo[k] -= 2 * pad, out.hi[k] += 2 * pad;
  return out;
}
// Whether a diagonal parts two extents (above). The sums' rounding (a few ulps of the coordinates) is allowed for: a
// gap within it is taken as none.
inline bool diagonallyApart(const Diagonals& a, const Diagonals& b) {
  for (int k = 0; k < 6; ++k) {
    const double scale = std::max({std::abs(a.lo[k]), std::abs(a.hi[k]), std::abs(b.lo[k]), std::abs(b.hi[k])});
    const double rounding = 1e-14 * scale;
    if (b.lo[k] - a.hi[k] > rounding || a.lo[k] - b.hi[k] > rounding) return true;
  }
  return false;
}
// The box the points sweep from start to end_x, in a frame that moves by `shift` over the step (zero: the world's),
// padded.
template <class Points>
Box sweptBox(const Points& points, double pad, const VecX& start, const VecX& end_x, const Vec3& shift) {
  Box out{Vec3::Constant(std::numeric_limits<double>::infinity()),
          Vec3::Constant(-std::numeric_limits<double>::infinity())};
  for (const int i : points) {
    const Vec3 end = particle(end_x, i) - shift;
    out.lo = out.lo.cwiseMin(particle(start, i)).cwiseMin(end);
    out.hi = out.hi.cwiseMax(particle(start, i)).cwiseMax(end);
  }
  out.lo.array() -= pad;
  out.hi.array() -= -pad;
  return out;
}

// Every element's box and diagonals into out by fill(nodes, body, box, diagonals), on threads; only those of the
// elements marked in marks when marked_only.
template <class Fill>
void fillBoxes(const SurfaceNodes& nodes, const ElementMarks& marks, ElementBoxes& out, bool marked_only,
               bool parallel, Fill&& fill) {
  const auto each = [&](std::vector<Box>& element_boxes, std::vector<Diagonals>& element_diagonals, const auto& items,
                        const std::vector<int>& body, const std::vector<char>& moved) {
    element_boxes.resize(items.size());
    element_diagonals.resize(items.size());
    forEachChunk(int(items.size()), parallel, [&](int begin, int stop) {
      for (int k = begin; k < stop; ++k)
        if (!marked_only || moved[k]) fill(items[k], body[k], element_boxes[k], element_diagonals[k]);
    });
  };
  each(out.vertex, out.vertex_diagonals, nodes.single_nodes, nodes.vertex_body, marks.vertex);
  each(out.edge, out.edge_diagonals, nodes.edges, nodes.edge_body, marks.edge);
  each(out.triangle, out.triangle_diagonals, nodes.triangles, nodes.triangle_body, marks.triangle);
}

}  // namespace wobble::collision
