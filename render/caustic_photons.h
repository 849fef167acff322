// Caustic photons: the sun's light through gelatine onto the surfaces around it (the jelly's coloured shadow), by a
// caustic photon map (Jensen 1996, "Global Illumination using Photon Maps"; Jensen 2001, "Realistic Image Synthesis
// Using Photon Mapping", ch. 9: the caustics photon map, photons shot towards specular objects only).
//
// Per frame, before the pixels, photons are shot from each sun towards the bounding sphere of the gelatine bodies
// (the sphere's disc across the photon's direction), through smooth interfaces (Fresnel's choice of reflection or
// refraction, as the path tracer's), Beer-Lambert absorption on the way; a photon that reaches a surface other than
// gelatine after at least one interface is stored there, and stops. Light-surface-...-surface paths the map cannot
// carry stay with the path tracer: a photon is dropped where it meets the gelatine's print layer, a rough interface
// or a scattering event, and one whose first hit is not gelatine (direct light: the path tracer's shadow rays).
// At a non-gelatine surface vertex the path tracer adds the map's density estimate (the photons within `radius`,
// weighted by a 2D biweight kernel, through the surface's BSDF), and drops the suns its continuations find through
// smooth interfaces alone (path_tracer.cpp): each light path is counted once. The clamp of indirect light applies to
// what remains.
//
// Parameters (CausticSettings):
//   photons  photons shot from each sun per map (0: no caustic map: the path tracer finds caustics by itself, as
//            sparkles). Cost: about four rays per photon, one map per four samples a pixel (CausticMaps).
//   radius   the density estimate's kernel radius (m). Bias: the caustic is blurred by the kernel (a feature
//            sharper than the radius is spread over it; the light is moved, not lost). Noise: a kernel holding k
//            photons has a relative error of about 1 / sqrt(k), a smooth blotch rather than single bright pixels.
//
// Many samples a pixel read several independent maps (CausticMaps below), so a converged still's caustic converges too.
//
// Determinism: photon i of sun j in map m is a pure function of (frame, m, j, i): its emission is point i of an
// Owen-scrambled Sobol sequence seeded by the frame, the map and the sun (position on the disc, direction in the sun's
// cone, instant in the shutter), its later choices hashed from (frame, m, j, i, event). Photons are traced in parallel
// into their own slots and kept in index order, and a gather sums them in a fixed order: the map and the pixels do not
// depend on the thread count, and tiles only read the map.
#pragma once
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "render/bounds.h"
#include "render/color.h"

namespace wobble::render {

class Scene;

struct CausticSettings {
  int photons = 0;      // per sun per map; 0: off
  float radius = 0.1f;  // m
};

struct CausticPhoton {
  Eigen::Vector3f p;   // where it landed
  Eigen::Vector3f wi;  // unit, towards where it came from
  Color power;         // flux (W)
};

// The sphere the photons are shot at: around every gelatine shape's bounds over the shutter. One per committed
// scene, shared by its maps.
struct CausticTarget {
  Eigen::Vector3f centre = Eigen::Vector3f::Zero();
  float radius = 0;  // 0: no gelatine in the scene
  static CausticTarget of(const Scene& scene);
};

class CausticMap {
 public:
  CausticMap() = default;
  // Shoots the photons of every sun of a committed scene at its target (CausticTarget::of(scene)). motion_blur: each
  // photon at its own instant of the shutter (Ray::time), as the camera's samples; else at time 0. `index`: which of
  // a frame's maps (CausticMaps).
  static CausticMap shoot(const Scene& scene, const CausticTarget& target, const CausticSettings& settings,
                          std::uint32_t frame, bool motion_blur, std::uint32_t index = 0);

  bool empty() const { return photons_.empty(); }
  std::size_t size() const { return photons_.size(); }
  float radius() const { return radius_; }
  const std::vector<CausticPhoton>& photons() const { return photons_; }

  // For every photon within the radius of p that came from the side of the unit normal n: use(wi, power x kernel),
  // the kernel in 1/m^2 (its integral over the disc is 1). In a fixed order: cell by cell, each cell's photons in
  // index order.
  template <class Use>
  void gather(const Eigen::Vector3f& p, const Eigen::Vector3f& n, const Use& use) const;

 private:
  static constexpr std::uint32_t kEmpty = ~0u;
  Eigen::Vector3i cell(const Eigen::Vector3f& p) const {
    return ((p - origin_) / cell_size_).array().floor().cast<int>();
  }
  std::size_t bucket(const Eigen::Vector3i& c) const {
    const std::uint32_t h =
        std::uint32_t(c.x()) * 73856093u ^ std::uint32_t(c.y()) * 19349663u ^ std::uint32_t(c.z()) * 83492791u;
    return h & (starts_.size() - 2);
  }

  float radius_ = 0, cell_size_ = 1;
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  Bounds reach_;  // the photons' box grown by the radius: points outside it gather nothing
  std::vector<CausticPhoton> photons_;
  std::vector<Eigen::Vector3i> cells_;  // each photon's grid cell
  // A hashed grid of cells twice the radius wide: bucket b's photons (indices into photons_, in order) are
  // order_[starts_[b] .. starts_[b + 1]); starts_ has a power of two plus one entries.
  std::vector<std::uint32_t> starts_, order_;
};

// A frame's maps, independent (each its own photons): samples 0-3 of every pixel read the first, 4-7 the second and
// so on, up to kMaxMaps maps, then round again. A still made of many samples thus averages many maps, and its
// caustic converges with the samples (to the kernel's blur) as the rest of the picture does; one or two samples a
// pixel (the default) read one map.
class CausticMaps {
 public:
  static constexpr std::uint32_t kSamplesPerMap = 4, kMaxMaps = 32;
  CausticMaps(const Scene& scene, const CausticSettings& settings, std::uint32_t frame, bool motion_blur)
      : scene_(&scene),
        target_(CausticTarget::of(scene)),
        settings_(settings),
        frame_(frame),
        motion_blur_(motion_blur) {}
  // Shoots the maps that samples 0 .. samples - 1 read and are not there yet (the renderer, before each pass).
  void cover(int samples);
  // The map of a sample below what cover() was given.
  const CausticMap& forSample(std::uint32_t sample) const { return maps_[(sample / kSamplesPerMap) % kMaxMaps]; }
  std::size_t size() const { return maps_.size(); }

 private:
  const Scene* scene_;
  CausticTarget target_;
  CausticSettings settings_;
  std::uint32_t frame_;
  bool motion_blur_;
  std::vector<CausticMap> maps_;
};

template <class Use>
void CausticMap::gather(const Eigen::Vector3f& p, const Eigen::Vector3f& n, const Use& use) const {
  if (photons_.empty() || !reach_.contains(p)) return;
  const float r2 = radius_ * radius_, norm = 3.0f / (3.14159265f * r2);
  // The query's sphere meets at most two cells along each axis.
  const Eigen::Vector3i lo = cell(p - Eigen::Vector3f::Constant(radius_)),
                        hi = cell(p + Eigen::Vector3f::Constant(radius_));
  for (int z = lo.z(); z <= hi.z(); ++z)
    for (int y = lo.y(); y <= hi.y(); ++y)
      for (int x = lo.x(); x <= hi.x(); ++x) {
        const Eigen::Vector3i c(x, y, z);
        const std::size_t b = bucket(c);
        for (std::uint32_t k = starts_[b]; k < starts_[b + 1]; ++k) {
          const std::uint32_t i = order_[k];
          if (cells_[i] != c) continue;  // another cell sharing the bucket
          const CausticPhoton& ph = photons_[i];
          const float d2 = (ph.p - p).squaredNorm();
          if (d2 >= r2 || ph.wi.dot(n) <= 0) continue;
          const float s = 1.0f - d2 / r2;
          use(ph.wi, ph.power * (norm * s * s));
        }
      }
}

}  // namespace wobble::render
