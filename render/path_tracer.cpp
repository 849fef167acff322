// The path tracer: next-event estimation of suns, area lights and the sky, BSDF-sampled bounces, MIS between them.
#include "render/path_tracer.h"

#include <algorithm>

#include "render/bsdf.h"
#include "render/camera.h"
#include "render/scene.h"

namespace wobble::render {

namespace {

// Veach's power heuristic (beta = 2): the weight of a sample drawn with density `chosen` against another strategy
// that could have drawn it with density `other`.
// Russian roulette's least chance of continuing: bounds the weight 1 / q a surviving path gets.
constexpr float kMinContinuation = 0.05f;

float powerHeuristic(float chosen, float other) {
  const float a = chosen * chosen, b = other * other;
  return a > 0 ? a / (a + b) : 0.0f;
}

// The first hit's pixel footprint in UV space: where the camera's neighbouring pixel rays (differentials ddx, ddy)
// meet the hit's tangent plane, mapped through the surface's UV parametrisation (least squares, as pbrt).
TextureFootprint footprint(const Ray& ray, const Camera* camera, const SurfaceHit& hit) {
  TextureFootprint f;
  if (!camera) return f;
  Eigen::Vector3f ddx, ddy;
  camera->differentials(ray.direction, ddx, ddy);
  const float a11 = hit.dpdu.squaredNorm(), a12 = hit.dpdu.dot(hit.dpdv), a22 = hit.dpdv.squaredNorm();
  const float det = a11 * a22 - a12 * a12;
  if (!(det > 1e-20f)) return f;
  const float plane = hit.ng.dot(hit.p - ray.origin);
  const auto toUv = [&](const Eigen::Vector3f& dd) {
    const Eigen::Vector3f d = ray.direction + dd;
    const Eigen::Vector3f dp = ray.origin + (plane / hit.ng.dot(d)) * d - hit.p;
    const float b1 = hit.dpdu.dot(dp), b2 = hit.dpdv.dot(dp);
    return Eigen::Vector2f((a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det);
  };
  f.duvdx = toUv(ddx);
  f.duvdy = toUv(ddy);
  return f;
}

}  // namespace

PathContext::PathContext(const Scene& scene_, const PathSettings& settings_)
    : scene(scene_), settings(settings_), sky(scene_.lights.sky), sky_distribution(scene_.lights.sky) {
  sky.up.normalize();
  for (const SunLight& sun : scene.lights.suns) suns.emplace_back(sun);
  settings.sample_sky = settings.sample_sky && !sky_distribution.empty();
  layout.lights = int(scene.lights.suns.size() + scene.lights.rects.size()) + (settings.sample_sky ? 1 : 0);
}

Eigen::Vector3f offsetFromSurface(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  return p + (1e-4f * (1.0f + p.cwiseAbs().maxCoeff())) * n;
}

PathResult tracePath(const PathContext& context, Ray ray, const CameraSample& camera, const PixelSampler& sampler,
                     std::uint32_t sample) {
  const Scene& scene = context.scene;
  const Lights& lights = scene.lights;
  const SampleLayout& layout = context.layout;
  const int max_bounces = context.settings.max_bounces;
  PathResult result;

  // Light reaching the camera is summed in two parts, split at the first surface by the lobe it leaves by: `diffuse`
  // (divided by that surface's base colour) and `other` (coat, and sky seen directly). t_diffuse and t_other are the
  // path's throughput beyond the first surface in those two parts.
  Color diffuse = Color::Zero(), other = Color::Zero();
  Color t_diffuse = Color::Zero(), t_other = Color::Ones();
  Color first_base = Color::Zero();
  float previous_pdf = 0;                        // density of the BSDF sample that made this ray; 0 for the camera ray
  const auto arrive = [&](const Color& light) {  // light arriving along the path's current ray
    diffuse += t_diffuse.cwiseProduct(light);
    other += t_other.cwiseProduct(light);
  };

  // Suns and area lights found by BSDF continuations: MIS-weighted, or fully when light samples are off.
  const bool bsdf_finds_lights = context.settings.mis || !context.settings.light_samples;
  const auto foundWeight = [&](float light_pdf) {
    return context.settings.light_samples ? powerHeuristic(previous_pdf, light_pdf) : 1.0f;
  };
  int leaving = -1;  // the surface the current ray starts on (none for the camera ray)
  for (int bounce = 0;; ++bounce) {
    ++result.rays;
    auto hit = scene.intersect(ray, leaving);
    if (bounce > 0 && bsdf_finds_lights) {  // a BSDF continuation may pass an area light before what it hits
      const float tmax = hit ? hit->t : ray.tfar;
      for (const RectLight& rect : lights.rects) {
        const LightHit h = rectAlongRay(rect, ray.origin, ray.direction, tmax);
        if (h.pdf > 0) arrive(h.radiance * foundWeight(h.pdf));
      }
    }
    if (!hit) {
      Color light = context.sky.eval(ray.direction);
      if (bounce > 0) {
        if (context.settings.sample_sky)
          light *= powerHeuristic(previous_pdf, context.sky_distribution.pdf(ray.direction));
        for (const SunCone& sun : context.suns) {
          const LightHit h = sunInDirection(sun, ray.direction);
          if (h.pdf > 0 && bsdf_finds_lights) light += h.radiance * foundWeight(h.pdf);
        }
      }
      arrive(light);
      break;
    }
    const Eigen::Vector3f wo = -ray.direction;
    // Two-sided shading: turn both normals to the side the ray came from.
    const Eigen::Vector3f ng = hit->ng.dot(wo) >= 0 ? hit->ng : Eigen::Vector3f(-hit->ng);
    Eigen::Vector3f ns = hit->ns.dot(ng) >= 0 ? hit->ns : Eigen::Vector3f(-hit->ns);
    if (ns.dot(wo) <= 0) ns = ng;  // interpolated normal facing away from the viewer: shade flat instead of black
    const Material& material = scene.material(hit->material);
    Color base;
    if (bounce == 0 && material.texture) {
      scene.uvDerivatives(*hit);
      TextureFootprint f = footprint(ray, camera.camera, *hit);
      f.jitter = sampler.get2D(sample, SampleLayout::kTexture);
      const Eigen::Vector2f centre = hit->uv - camera.offset.x() * f.duvdx - camera.offset.y() * f.duvdy;
      base = material.baseColor(centre.allFinite() ? centre : hit->uv, f);
    } else {
      base = material.baseColor(hit->uv);
    }
    if (bounce == 0) {
      result.hit = true;
      result.albedo = first_base = base;
      result.normal = ns;
      result.position = hit->p;
    }
    const Bsdf bsdf(material, base, ns, wo);
    const Eigen::Vector3f origin = offsetFromSurface(hit->p, ng);
    const bool continues = bounce < max_bounces;
    // The chance of continuing from here: 1 for the first continuation; with Russian roulette, from the second on,
    // the path's throughput so far (its largest channel, at most 1), as pbrt-v4: paths that carry little light stop
    // early, and the survivors' weight / q stays near 1, so the roulette adds little noise. The BSDF strategy's
    // density as MIS sees it is what BSDF sampling draws times q.
    float q = continues ? 1.0f : 0.0f;
    if (continues && bounce > 0 && context.settings.roulette)
      q = std::clamp((first_base.cwiseProduct(t_diffuse) + t_other).maxCoeff(), kMinContinuation, 1.0f);

    // Light arriving at this surface from direction wi, already divided by its sampling density and weighted.
    const auto reflect = [&](const Eigen::Vector3f& wi, const Color& incoming) {
      const BsdfLobes f = bsdf.evalLobes(wi);
      const float cos_i = ns.dot(wi);
      if (bounce == 0) {
        diffuse += (f.diffuse * cos_i) * incoming;
        other += (f.specular * cos_i) * incoming;
      } else {
        arrive(((f.diffuse * cos_i) * base.array() + f.specular * cos_i).matrix().cwiseProduct(incoming));
      }
    };
    const auto sampleLight = [&](const LightSample& s) {
      if (!context.settings.light_samples || s.value.isZero() || ns.dot(s.wi) <= 0) return;
      ++result.rays;
      if (!unoccluded(scene, s.shadow, hit->shape)) return;
      // With no continuation from here, light samples are the only strategy: full weight.
      const bool combined = continues && s.pdf > 0 && context.settings.mis;
      const float weight = combined ? powerHeuristic(s.pdf, q * bsdf.pdf(s.wi)) : 1.0f;
      reflect(s.wi, s.value * weight);
    };
    int light_index = 0;
    for (const SunCone& sun : context.suns) {
      const Eigen::Vector2f u = sampler.get2D(sample, layout.light(bounce, light_index++));
      sampleLight(sampleSun(sun, origin, ng, u.x(), u.y()));
    }
    for (const RectLight& rect : lights.rects) {
      const Eigen::Vector2f u = sampler.get2D(sample, layout.light(bounce, light_index++));
      sampleLight(sampleRect(rect, origin, ng, u.x(), u.y()));
    }
    if (!continues) break;
    if (context.settings.sample_sky) {  // the sky is reached by continuations only, so only where one follows
      const Eigen::Vector2f u = sampler.get2D(sample, layout.light(bounce, light_index++));
      float pdf = 0;
      const Eigen::Vector3f wi = context.sky_distribution.sample(u.x(), u.y(), pdf);
      if (pdf > 0 && wi.dot(ng) > 0 && ns.dot(wi) > 0) {
        ++result.rays;
        if (unoccluded(scene, Ray{origin, wi}, hit->shape))
          reflect(wi, context.sky.eval(wi) * (powerHeuristic(pdf, q * bsdf.pdf(wi)) / pdf));
      }
    }

    if (q < 1 && sampler.get1D(sample, layout.roulette(bounce)) >= q) break;
    const float u_lobe = sampler.get1D(sample, layout.bsdfLobe(bounce));
    const Eigen::Vector2f u = sampler.get2D(sample, layout.bsdfDirection(bounce));
    const auto s = bsdf.sample(u_lobe, u.x(), u.y());
    if (!s || s->wi.dot(ng) <= 0) break;  // absorbed, or headed into the surface it left
    if (bounce == 0) {
      t_diffuse = Color::Constant(s->lobes.diffuse / q);
      t_other = Color::Constant(s->lobes.specular / q);
    } else {
      t_diffuse = t_diffuse.cwiseProduct(s->weight) / q;
      t_other = t_other.cwiseProduct(s->weight) / q;
    }
    if (t_diffuse.isZero() && t_other.isZero()) break;
    previous_pdf = q * s->pdf;
    ray = Ray{origin, s->wi};
    leaving = hit->shape;
  }
  result.diffuse = first_base.cwiseProduct(diffuse);
  result.diffuse_demodulated = luminance(diffuse);
  result.radiance = result.diffuse + other;
  return result;
}

bool unoccluded(const Scene& scene, const Ray& shadow, int leaving) { return !scene.occluded(shadow, leaving); }

}  // namespace wobble::render
