// The path tracer: next-event estimation of suns and area lights, BSDF-sampled bounces, sky on escape.
#include "integrator.h"

#include "bsdf.h"
#include "scene.h"

namespace wobble::render {

Eigen::Vector3f offsetFromSurface(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  return p + (1e-4f * (1.0f + p.cwiseAbs().maxCoeff())) * n;
}

PathResult tracePath(const Scene& scene, Ray ray, Rng& rng, int max_bounces) {
  PathResult result;
  Color throughput = Color::Ones();
  for (int bounce = 0;; ++bounce) {
    ++result.rays;
    const auto hit = scene.intersect(ray);
    if (!hit) {
      result.radiance += throughput.cwiseProduct(scene.lights.sky.eval(ray.direction));
      break;
    }
    const Eigen::Vector3f wo = -ray.direction;
    // Two-sided shading: turn both normals to the side the ray came from.
    const Eigen::Vector3f ng = hit->ng.dot(wo) >= 0 ? hit->ng : Eigen::Vector3f(-hit->ng);
    Eigen::Vector3f ns = hit->ns.dot(ng) >= 0 ? hit->ns : Eigen::Vector3f(-hit->ns);
    if (ns.dot(wo) <= 0) ns = ng;  // interpolated normal facing away from the viewer: shade flat instead of black
    const Material& material = scene.material(hit->material);
    const Color base = material.baseColor(hit->uv);
    if (bounce == 0) {
      result.hit = true;
      result.albedo = base;
      result.normal = ns;
      result.position = hit->p;
    }
    const Bsdf bsdf(material, base, ns);
    const Eigen::Vector3f origin = offsetFromSurface(hit->p, ng);

    const auto addLight = [&](const LightSample& s) {
      ++result.rays;
      if (s.value.isZero()) return;
      const float cos_s = ns.dot(s.wi);
      if (cos_s <= 0) return;
      result.radiance += throughput.cwiseProduct(bsdf.eval(wo, s.wi)).cwiseProduct(s.value) * cos_s;
    };
    for (const SunLight& sun : scene.lights.suns) {
      const float u1 = rng.next(), u2 = rng.next();
      addLight(sampleSun(scene, sun, origin, ng, u1, u2));
    }
    for (const RectLight& rect : scene.lights.rects) {
      const float u1 = rng.next(), u2 = rng.next();
      addLight(sampleRect(scene, rect, origin, ng, u1, u2));
    }

    if (bounce >= max_bounces) break;
    const float ul = rng.next(), u1 = rng.next(), u2 = rng.next();
    const auto sample = bsdf.sample(wo, ul, u1, u2);
    if (!sample || sample->wi.dot(ng) <= 0) break;  // absorbed, or headed into the surface it left
    throughput = throughput.cwiseProduct(sample->weight);
    if (throughput.isZero()) break;
    ray = Ray{origin, sample->wi};
  }
  return result;
}

}  // namespace wobble::render
