// The path tracer: next-event estimation of suns, area lights and the sky, BSDF-sampled bounces, MIS between them.
#include "render/path_tracer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "render/bsdf.h"
#include "render/camera.h"
#include "render/dielectric.h"
#include "render/scene.h"

namespace wobble::render {

namespace {

// Veach's power heuristic (beta = 2): the weight of a sample drawn with density `chosen` against another strategy
// that could have drawn it with density `other`.
// Russian roulette's least chance of continuing: bounds the weight 1 / q a surviving path gets.
constexpr float kMinContinuation = 0.05f;
// Gelatine: the most interfaces (reflections and refractions, as Cycles' 12 transmission bounces) and scattering
// events a path meets; neither counts against max_bounces.
constexpr int kMaxInterfaceEvents = 64, kMaxScatterEvents = 128;

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

// Motion blur: over the shutter the surface slides under the pixel (its own motion and the eye's, camera.h), so the
// hit's UV moves by duv/dt. The footprint is widened by that motion, in pixels along each of its axes (the bounding
// box of the pixel swept along the motion, as the textures filter a footprint's bounding box anyway), and its centre
// is moved to the shutter's middle: every sample of the pixel again sees the same filtered texture, and the motion
// blurs the texture smoothly instead of as per-sample noise. Nothing changes when nothing moves.
void blurFootprint(TextureFootprint& f, Eigen::Vector2f& centre, const Ray& ray, const Camera& camera,
                   const SurfaceHit& hit) {
  const Eigen::Vector3f slide = camera.params().shutter_motion - hit.dpdt;  // the eye's motion relative to the surface
  if (slide.isZero()) return;
  const float nd = hit.ng.dot(ray.direction);
  const float a11 = hit.dpdu.squaredNorm(), a12 = hit.dpdu.dot(hit.dpdv), a22 = hit.dpdv.squaredNorm();
  const float det_uv = a11 * a22 - a12 * a12;
  if (!(std::abs(nd) > 1e-6f) || !(det_uv > 1e-20f)) return;
  // Moving the eye by `slide` moves the point it sees on the (tangent) plane by this much (footprint() above):
  const Eigen::Vector3f dp = slide - ray.direction * (hit.ng.dot(slide) / nd);
  const float b1 = hit.dpdu.dot(dp), b2 = hit.dpdv.dot(dp);
  const Eigen::Vector2f duvdt((a22 * b1 - a12 * b2) / det_uv, (a11 * b2 - a12 * b1) / det_uv);
  // duvdt = a duvdx + b duvdy: the motion in pixels.
  const float det = f.duvdx.x() * f.duvdy.y() - f.duvdx.y() * f.duvdy.x();
  if (!(std::abs(det) > 1e-20f) || !duvdt.allFinite()) return;
  const float a = (duvdt.x() * f.duvdy.y() - duvdt.y() * f.duvdy.x()) / det;
  const float b = (f.duvdx.x() * duvdt.y() - f.duvdx.y() * duvdt.x()) / det;
  centre -= (ray.time - 0.5f) * duvdt;
  f.duvdx *= 1 + std::abs(a);
  f.duvdy *= 1 + std::abs(b);
}

}  // namespace

PathContext::PathContext(const Scene& scene_, const PathSettings& settings_)
    : scene(scene_), settings(settings_), background(scene_.lights) {
  for (const SunLight& sun : scene.lights.suns) suns.emplace_back(sun);
  settings.sample_sky = settings.sample_sky && !background.empty();
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

  // Light reaching the camera is summed in two parts, split at the first non-specular vertex (the first surface,
  // unless the path first passes smooth gelatine) by the lobe it leaves by: `diffuse` (divided by that surface's
  // base colour) and `other` (coat, gelatine, and sky seen directly or through gelatine). t_diffuse and t_other are
  // the path's throughput beyond that vertex in those two parts; before it t_other is the throughput of the
  // specular prefix (the smooth interfaces and the absorption met so far).
  Color diffuse = Color::Zero(), other = Color::Zero();
  Color t_diffuse = Color::Zero(), t_other = Color::Ones();
  Color first_base = Color::Zero();
  bool split = false;  // the first non-specular vertex is behind
  const auto weigh = [&](const Color& w) {
    t_diffuse = t_diffuse.cwiseProduct(w);
    t_other = t_other.cwiseProduct(w);
  };
  float previous_pdf = 0;  // density of the BSDF sample that made this ray; 0 for the camera ray
  // What the vertex that made this ray sampled itself, so that a light this ray finds is weighted against it (MIS)
  // or, where that vertex could not sample it (a smooth interface, a scattering event), counted fully.
  bool previous_sampled_lights = true, previous_sampled_sky = context.settings.sample_sky;
  const auto arrive = [&](const Color& light) {  // light arriving along the path's current ray
    diffuse += t_diffuse.cwiseProduct(light);
    other += t_other.cwiseProduct(light);
  };

  // The guides' position of a vertex met through smooth interfaces: its virtual image, as far along the camera ray
  // as the path has come (a reflection's image lies behind the mirror, never behind the camera).
  const Ray camera_ray = ray;
  const float time = ray.time;  // every ray of the path is traced at the camera ray's instant (motion blur)
  const auto atTime = [time](Ray r) {
    r.time = time;
    return r;
  };
  float travelled = 0;
  const auto guidePosition = [&](const Eigen::Vector3f& p, float t) {
    return travelled == 0 ? p : Eigen::Vector3f(camera_ray.at(travelled + t));
  };
  // One sample of every sun and area light seen from origin above the normal n, each from its own slot, handed to
  // use(LightSample); returns the next slot's light index.
  const auto sampleLights = [&](int vertex, const Eigen::Vector3f& origin, const Eigen::Vector3f& n, const auto& use) {
    int light_index = 0;
    for (const SunCone& sun : context.suns) {
      const Eigen::Vector2f u = sampler.get2D(sample, layout.light(vertex, light_index++));
      use(sampleSun(sun, origin, n, u.x(), u.y()));
    }
    for (const RectLight& rect : lights.rects) {
      const Eigen::Vector2f u = sampler.get2D(sample, layout.light(vertex, light_index++));
      use(sampleRect(rect, origin, n, u.x(), u.y()));
    }
    return light_index;
  };
  int leaving = -1;                  // the surface the current ray starts on (none for the camera ray)
  const Material* medium = nullptr;  // the gelatine the current ray travels through
  int bounce = 0;                    // continuations from surfaces (max_bounces counts them)
  int interface_events = 0, scatter_events = 0;
  for (int vertex = 0;; ++vertex) {
    ++result.rays;
    auto hit = scene.intersect(ray, leaving);
    if (medium) {
      // Beer-Lambert absorption to the next surface or, in a scattering medium, to a collision drawn on the way.
      const float t_hit = hit ? hit->t : std::numeric_limits<float>::infinity();
      float t = t_hit;
      if (medium->scatter > 0) {
        const float u = sampler.get1D(sample, SampleLayout::medium(vertex));
        t = std::min(t_hit, -std::log1p(-u) / medium->scatter);
      }
      if (!hit && t == t_hit) {  // left through an open surface: no longer inside anything
        medium = nullptr;
      } else {
        weigh((-medium->absorption * t).array().exp().matrix());
        if (t < t_hit) {  // scattered: an isotropic phase function, the throughput times the albedo
          weigh(medium->scatter_albedo);
          const Eigen::Vector3f p = ray.at(t);
          if (!split) {
            split = true, result.hit = true;
            result.albedo = first_base = t_other;
            result.normal = -ray.direction, result.position = guidePosition(p, t);
            t_diffuse = Color::Zero();
          }
          if (++scatter_events > kMaxScatterEvents || (t_diffuse.isZero() && t_other.isZero())) break;
          const Eigen::Vector2f u = sampler.get2D(sample, layout.bsdfDirection(vertex));
          const float z = 1.0f - 2.0f * u.x(), r = std::sqrt(std::max(0.0f, 1.0f - z * z));
          const Eigen::Vector2f phi = cosSin2Pi(u.y());
          travelled += t;
          ray = atTime(Ray{p, Eigen::Vector3f(r * phi.x(), r * phi.y(), z)});
          previous_pdf = 1.0f / (4.0f * std::numbers::pi_v<float>);
          previous_sampled_lights = previous_sampled_sky = false;  // lights are outside: a shadow ray from here is
          leaving = -1;                                            // always blocked by the body's own surface
          continue;
        }
      }
    }
    const bool lights_weighed = previous_sampled_lights;
    if (vertex > 0 && (context.settings.mis || !lights_weighed)) {  // a continuation may pass an area light
      const float tmax = hit ? hit->t : ray.tfar;
      for (const RectLight& rect : lights.rects) {
        const LightHit h = rectAlongRay(rect, ray.origin, ray.direction, tmax);
        if (h.pdf > 0) arrive(h.radiance * (lights_weighed ? powerHeuristic(previous_pdf, h.pdf) : 1.0f));
      }
    }
    if (!hit) {
      Color light = context.background.eval(ray.direction);
      if (vertex > 0) {
        if (context.settings.sample_sky && previous_sampled_sky)
          light *= powerHeuristic(previous_pdf, context.background.pdf(ray.direction));
        for (const SunCone& sun : context.suns) {
          const LightHit h = sunInDirection(sun, ray.direction);
          if (h.pdf > 0 && (context.settings.mis || !lights_weighed))
            light += h.radiance * (lights_weighed ? powerHeuristic(previous_pdf, h.pdf) : 1.0f);
        }
      }
      arrive(light);
      break;
    }
    const Eigen::Vector3f wo = -ray.direction;
    const Material& material = scene.material(hit->material);
    // Gelatine: its print layer (a diffuse surface, shaded below) with probability `print`, else the clear interface.
    using Branch = CameraSample::Branch;
    const Branch branch = vertex == 0 && material.dielectric ? camera.branch : Branch::Drawn;
    if (vertex == 0 && material.dielectric) result.gelatine_first = true, result.print = material.print;
    const bool printed = branch == Branch::Drawn
                             ? material.print > 0 && sampler.get1D(sample, SampleLayout::print(vertex)) < material.print
                             : branch == Branch::Print;
    if (material.dielectric && !printed) {
      const Eigen::Vector3f& outward = hit->ng;
      const Eigen::Vector3f n = hit->ns.dot(outward) >= 0 ? hit->ns : Eigen::Vector3f(-hit->ns);
      const bool entering = outward.dot(wo) > 0;
      const DielectricBsdf bsdf(material.ior, material.roughness, n, wo);
      if (!split) {  // the guides: this interface, unless a non-specular vertex follows
        result.hit = true;
        result.albedo = t_other;
        result.normal = entering ? outward : Eigen::Vector3f(-outward);
        result.position = guidePosition(hit->p, hit->t);
        if (!bsdf.smooth()) split = true, first_base = t_other, t_diffuse = Color::Zero();
      }
      const bool continues = ++interface_events <= kMaxInterfaceEvents;
      if (!bsdf.smooth()) {  // a rough interface: suns and area lights outside, seen by reflection or transmission
        const Eigen::Vector3f origin = offsetFromSurface(hit->p, outward);
        const auto sampleLight = [&](const LightSample& s) {
          if (s.value.isZero()) return;
          const float f = bsdf.eval(s.wi);
          if (!(f > 0)) return;
          ++result.rays;
          if (!unoccluded(scene, atTime(s.shadow), hit->shape)) return;
          const bool combined = continues && s.pdf > 0 && context.settings.mis;
          const float weight = combined ? powerHeuristic(s.pdf, bsdf.pdf(s.wi)) : 1.0f;
          arrive(s.value * (f * std::abs(n.dot(s.wi)) * weight));
        };
        sampleLights(vertex, origin, outward, sampleLight);
      }
      if (!continues) break;
      float u_lobe = sampler.get1D(sample, layout.bsdfLobe(vertex));
      if (bsdf.smooth() && branch != Branch::Drawn) {  // the branch asked for: below or above the reflectance
        result.reflectance = fresnelDielectric(std::abs(n.dot(wo)), entering ? material.ior : 1 / material.ior);
        u_lobe = branch == Branch::Reflect ? 0.0f : std::nextafter(1.0f, 0.0f);
      }
      const Eigen::Vector2f u = sampler.get2D(sample, layout.bsdfDirection(vertex));
      const auto s = bsdf.sample(u_lobe, u.x(), u.y());
      if (!s) break;
      const bool outside = s->wi.dot(outward) > 0;
      if (s->transmitted == (outside == entering)) break;  // the shading normal sent it to the wrong side
      weigh(Color::Constant(s->weight));
      if (t_diffuse.isZero() && t_other.isZero()) break;
      if (s->transmitted) medium = entering ? &material : nullptr;
      previous_pdf = s->pdf;
      previous_sampled_lights = !bsdf.smooth();
      previous_sampled_sky = false;
      travelled += hit->t;
      ray = atTime(Ray{offsetFromSurface(hit->p, outside ? outward : Eigen::Vector3f(-outward)), s->wi});
      leaving = hit->shape;
      continue;
    }
    const bool first = !split;
    // Two-sided shading: turn both normals to the side the ray came from.
    const Eigen::Vector3f ng = hit->ng.dot(wo) >= 0 ? hit->ng : Eigen::Vector3f(-hit->ng);
    Eigen::Vector3f ns = hit->ns.dot(ng) >= 0 ? hit->ns : Eigen::Vector3f(-hit->ns);
    if (ns.dot(wo) <= 0) ns = ng;  // interpolated normal facing away from the viewer: shade flat instead of black
    Color base;
    if (vertex == 0 && material.texture) {
      scene.uvDerivatives(*hit);
      TextureFootprint f = footprint(ray, camera.camera, *hit);
      f.jitter = sampler.get2D(sample, SampleLayout::kTexture);
      Eigen::Vector2f centre = hit->uv - camera.offset.x() * f.duvdx - camera.offset.y() * f.duvdy;
      if (camera.camera) blurFootprint(f, centre, ray, *camera.camera, *hit);
      base = material.baseColor(centre.allFinite() ? centre : hit->uv, f);
    } else {
      base = material.baseColor(hit->uv);
    }
    const Color prefix = first ? t_other : Color::Ones();  // throughput of the specular prefix, if any
    if (first) {
      split = true;
      result.hit = true;
      result.albedo = first_base = prefix.cwiseProduct(base);
      result.normal = ns;
      result.position = guidePosition(hit->p, hit->t);
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
      if (first) {
        diffuse += (f.diffuse * cos_i) * incoming;
        other += prefix.cwiseProduct((f.specular * cos_i) * incoming);
      } else {
        arrive(((f.diffuse * cos_i) * base.array() + f.specular * cos_i).matrix().cwiseProduct(incoming));
      }
    };
    const auto sampleLight = [&](const LightSample& s) {
      if (!context.settings.light_samples || s.value.isZero() || ns.dot(s.wi) <= 0) return;
      ++result.rays;
      if (!unoccluded(scene, atTime(s.shadow), hit->shape)) return;
      // With no continuation from here, light samples are the only strategy: full weight.
      const bool combined = continues && s.pdf > 0 && context.settings.mis;
      const float weight = combined ? powerHeuristic(s.pdf, q * bsdf.pdf(s.wi)) : 1.0f;
      reflect(s.wi, s.value * weight);
    };
    int light_index = sampleLights(vertex, origin, ng, sampleLight);
    if (!continues) break;
    if (context.settings.sample_sky) {  // the sky is reached by continuations only, so only where one follows
      const Eigen::Vector2f u = sampler.get2D(sample, layout.light(vertex, light_index++));
      float pdf = 0;
      const Eigen::Vector3f wi = context.background.sample(u.x(), u.y(), pdf);
      if (pdf > 0 && wi.dot(ng) > 0 && ns.dot(wi) > 0) {
        ++result.rays;
        if (unoccluded(scene, atTime(Ray{origin, wi}), hit->shape))
          reflect(wi, context.background.eval(wi) * (powerHeuristic(pdf, q * bsdf.pdf(wi)) / pdf));
      }
    }

    if (q < 1 && sampler.get1D(sample, layout.roulette(vertex)) >= q) break;
    const float u_lobe = sampler.get1D(sample, layout.bsdfLobe(vertex));
    const Eigen::Vector2f u = sampler.get2D(sample, layout.bsdfDirection(vertex));
    const auto s = bsdf.sample(u_lobe, u.x(), u.y());
    if (!s || s->wi.dot(ng) <= 0) break;  // absorbed, or headed into the surface it left
    if (first) {
      t_diffuse = Color::Constant(s->lobes.diffuse / q);
      t_other = prefix * (s->lobes.specular / q);
    } else {
      t_diffuse = t_diffuse.cwiseProduct(s->weight) / q;
      t_other = t_other.cwiseProduct(s->weight) / q;
    }
    if (t_diffuse.isZero() && t_other.isZero()) break;
    previous_pdf = q * s->pdf;
    previous_sampled_lights = context.settings.light_samples;
    previous_sampled_sky = context.settings.sample_sky;
    ray = atTime(Ray{origin, s->wi});
    leaving = hit->shape;
    ++bounce;
  }
  result.diffuse = first_base.cwiseProduct(diffuse);
  result.diffuse_demodulated = luminance(diffuse);
  result.radiance = result.diffuse + other;
  return result;
}

PathResult tracePathSplit(const PathContext& context, const Ray& ray, CameraSample camera, const PixelSampler& sampler,
                          std::uint32_t sample) {
  using Branch = CameraSample::Branch;
  camera.branch = Branch::Interface;
  PathResult first = tracePath(context, ray, camera, sampler, sample);
  if (!first.gelatine_first) return first;
  const float c = first.print, f = first.reflectance;
  struct Part {
    Branch branch;
    float weight;
  };
  const Part others[] = {{Branch::Reflect, (1 - c) * f}, {Branch::Print, c}};
  const float interface_weight = (1 - c) * (1 - f);
  PathResult sum;
  float guide_weight = -1;
  const auto add = [&](const PathResult& r, float w) {
    sum.radiance += w * r.radiance;
    sum.diffuse += w * r.diffuse;
    sum.diffuse_demodulated += w * r.diffuse_demodulated;
    sum.albedo += w * r.albedo;
    sum.normal += w * r.normal;
    if (r.hit && w > guide_weight) guide_weight = w, sum.position = r.position, sum.hit = true;
    sum.rays += r.rays;
  };
  add(first, interface_weight);
  for (const Part& part : others)
    if (part.weight > 0) {
      camera.branch = part.branch;
      add(tracePath(context, ray, camera, sampler, sample), part.weight);
    }
  return sum;
}

bool unoccluded(const Scene& scene, const Ray& shadow, int leaving) { return !scene.occluded(shadow, leaving); }

}  // namespace wobble::render
