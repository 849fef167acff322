// The caustic photon map: shooting photons from the suns through gelatine, and the hashed grid a gather reads
// (caustic_photons.h).
#include "render/caustic_photons.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <tbb/parallel_for.h>

#include "render/dielectric.h"
#include "render/lights.h"
#include "render/path_tracer.h"
#include "render/sampler.h"
#include "render/scene.h"

namespace wobble::render {

namespace {

// The later random choices of a photon (Fresnel, print, free path): hashed uniform numbers in [0, 1).
class PhotonRandom {
 public:
  PhotonRandom(std::uint32_t seed, std::uint32_t photon) : state_(sobol::hash(seed, photon)) {}
  float next() {
    state_ = sobol::hash(state_, ++count_);
    return sobol::toUnitFloat(state_);
  }

 private:
  std::uint32_t state_, count_ = 0;
};

// Traces one photon of flux `power` along `ray` into the scene; where it lands after at least one smooth interface
// on a surface that is not gelatine, returns it. sunlit(): whether sunlight reaches the ray's origin, asked only of a
// photon whose first hit is gelatine (most others are dropped for one ray).
template <class Sunlit>
std::optional<CausticPhoton> tracePhoton(const Scene& scene, Ray ray, Color power, PhotonRandom& random,
                                         const Sunlit& sunlit) {
  const Material* medium = nullptr;
  int leaving = -1;
  for (int events = 0; events <= kMaxInterfaceEvents; ++events) {
    const auto hit = scene.intersect(ray, leaving);
    if (medium) {  // absorption on the way; a scattering event ends the chain (the path tracer's)
      const float t = hit ? hit->t : std::numeric_limits<float>::infinity();
      if (medium->scatter > 0 && medium->freeFlight(random.next()) < t) return std::nullopt;
      if (hit) power = power.cwiseProduct(medium->transmittance(t));
    }
    if (!hit) return std::nullopt;
    const Material& material = scene.material(hit->material);
    if (events == 0 && (!material.dielectric || !sunlit())) return std::nullopt;
    if (!material.dielectric) {
      return CausticPhoton{hit->p, -ray.direction, power};  // (a first hit here is direct light: dropped above)
    }
    // Gelatine: its print layer and a rough interface are not part of a specular chain.
    if (material.print > 0 && random.next() < material.print) return std::nullopt;
    if (material.roughness > 0) return std::nullopt;
    // The smooth interface, as the path tracer crosses it (Path::crossInterface).
    const InterfaceCrossing crossing(*hit, ray.direction);
    const auto s = crossing.bsdf(material.ior, 0).sample(random.next(), 0.5f, 0.5f);
    if (!s) return std::nullopt;
    const std::optional<Ray> next = crossing.leave(*hit, *s);
    if (!next) return std::nullopt;
    if (s->transmitted) medium = crossing.entering ? &material : nullptr;
    ray = *next;
    leaving = hit->shape;
  }
  return std::nullopt;
}

}  // namespace

CausticTarget CausticTarget::of(const Scene& scene) {
  Bounds box;
  for (std::size_t id = 0; id < scene.shapeCount(); ++id)
    if (scene.material(scene.shapeView(ShapeId(id)).material).dielectric) box.extend(scene.bounds(ShapeId(id)));
  if (box.isEmpty()) return {};
  return {box.center(), 0.5f * box.diagonal().norm() * 1.001f};
}

void CausticMaps::cover(int samples) {
  const std::uint32_t count =
      std::clamp<std::uint32_t>((std::uint32_t(std::max(1, samples)) + kSamplesPerMap - 1) / kSamplesPerMap, 1,
                                kMaxMaps);
  while (maps_.size() < count)
    maps_.push_back(CausticMap::shoot(*scene_, target_, settings_, frame_, motion_blur_, std::uint32_t(maps_.size())));
}

CausticMap CausticMap::shoot(const Scene& scene, const CausticTarget& target, const CausticSettings& settings,
                             std::uint32_t frame, bool motion_blur, std::uint32_t index) {
  CausticMap map;
  if (settings.photons <= 0 || !(target.radius > 0) || scene.lights.suns.empty()) return map;
  map.radius_ = settings.radius;
  const std::size_t n = std::size_t(settings.photons);
  std::vector<std::optional<CausticPhoton>> slots(n * scene.lights.suns.size());
  const float disc_area = std::numbers::pi_v<float> * target.radius * target.radius;
  for (std::size_t j = 0; j < scene.lights.suns.size(); ++j) {
    const SunCone cone(scene.lights.suns[j]);
    // Each photon carries an equal share of the sun's flux through the disc: irradiance x area / count.
    const Color power = cone.sun->irradiance * (disc_area / float(n));
    const std::uint32_t seed = sobol::hash(sobol::hash(frame, index), 0x9e3779b9u + std::uint32_t(j));
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1024), [&](const tbb::blocked_range<std::size_t>& r) {
      // Per task (it caches seeds); a "pixel" per map and sun.
      const PixelSampler emission(SamplerKind::Sobol, (std::uint64_t(index) << 32) + 0x51ca0000u + j, frame);
      for (std::size_t i = r.begin(); i != r.end(); ++i) {
        const auto sample = std::uint32_t(i);
        // A direction in the sun's cone, a point on the target's disc across it, an instant in the shutter.
        const Eigen::Vector2f u_dir = emission.get2D(sample, 0), u_disc = emission.get2D(sample, 1);
        const Eigen::Vector3f to_sun = sampleSun(cone, target.centre, cone.axis, u_dir.x(), u_dir.y()).wi;
        const Frame across(to_sun);
        const float radius = target.radius * std::sqrt(u_disc.x());
        const Eigen::Vector2f phi = cosSin2Pi(u_disc.y());
        const Eigen::Vector3f origin =
            target.centre + target.radius * to_sun + radius * (phi.x() * across.s + phi.y() * across.t);
        const float time = motion_blur ? emission.get1D(sample, 2) : 0.0f;
        // Sunlight reaches the disc only where nothing stands between it and the sun.
        const auto sunlit = [&] {
          return !scene.occluded(Ray{origin, to_sun, 0, std::numeric_limits<float>::infinity(), time});
        };
        PhotonRandom random(seed, sample);
        slots[j * n + i] = tracePhoton(scene, Ray{origin, -to_sun, 0, std::numeric_limits<float>::infinity(), time},
                                       power, random, sunlit);
      }
    });
  }
  // Kept in index order, then bucketed by a stable counting sort: the same map whatever the thread count.
  for (auto& s : slots)
    if (s) map.photons_.push_back(*s);
  if (map.photons_.empty()) return map;
  map.cell_size_ = 2 * settings.radius;
  Bounds box;
  for (const CausticPhoton& p : map.photons_) box.extend(p.p);
  map.origin_ = box.min();
  map.reach_ = Bounds(box.min() - Eigen::Vector3f::Constant(settings.radius),
                      box.max() + Eigen::Vector3f::Constant(settings.radius));
  std::size_t buckets = 1;
  while (buckets < 2 * map.photons_.size()) buckets *= 2;
  map.starts_.assign(buckets + 1, 0);
  map.cells_.resize(map.photons_.size());
  for (std::size_t i = 0; i < map.photons_.size(); ++i) {
    map.cells_[i] = map.cell(map.photons_[i].p);
    ++map.starts_[map.bucket(map.cells_[i]) + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) map.starts_[b + 1] += map.starts_[b];
  map.order_.resize(map.photons_.size());
  std::vector<std::uint32_t> fill(map.starts_.begin(), map.starts_.end() - 1);
  for (std::size_t i = 0; i < map.photons_.size(); ++i)
    map.order_[fill[map.bucket(map.cells_[i])]++] = std::uint32_t(i);
  return map;
}

}  // namespace wobble::render
