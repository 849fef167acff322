// Bounds: a shape's axis-aligned box (Eigen's AlignedBox, empty until extended), padded for rounding, and whether a
// ray can meet it (the slab test). The Scene keeps each shape's bounds, to answer rays that leave a shape and
// provably miss everything else without asking Embree (scene.h).
#pragma once
#include <Eigen/Geometry>

#include "render/ray.h"

namespace wobble::render {

using Bounds = Eigen::AlignedBox3f;

// Grown on every side by `relative` of its largest coordinate's magnitude (at least of 1): room for the rounding of
// the points it was built from and of the slab test. An empty box stays empty.
Bounds padded(const Bounds& box, float relative);
// False only when the ray misses the box for t in [tnear, tfar].
bool mayHit(const Bounds& box, const Ray& ray);

}  // namespace wobble::render
