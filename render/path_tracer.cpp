// The path tracer: next-event estimation of suns, area lights and the sky, BSDF-sampled bounces, MIS between them.
// tracePath is one Path: its state (throughput, gathered light, what the last vertex sampled) and its steps, as
// pbrt-v4's VolPathIntegrator::Li reads: travel through the medium, add the emitters the ray passed or escaped to,
// then cross a gelatine interface or scatter at a surface. Light sampling sits in its own steps, outside the loop.
#include "render/path_tracer.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "render/bsdf.h"
#include "render/camera.h"
#include "render/caustic_photons.h"
#include "render/dielectric.h"
#include "render/scene.h"

namespace wobble::render {

namespace {

// Veach's power heuristic (beta = 2): the weight of a sample drawn with density `chosen` against another strategy
// that could have drawn it with density `other`.
// Russian roulette's least chance of continuing: bounds the weight 1 / q a surviving path gets.
constexpr float kMinContinuation = 0.05f;
// Gelatine: the most scattering events a path meets; they do not count against max_bounces (nor do its interfaces,
// kMaxInterfaceEvents).
constexpr int kMaxScatterEvents = 128;

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

PathContext::PathContext(const Scene& scene_, const PathSettings& settings_, const CausticMaps* caustics_)
    : scene(scene_), settings(settings_), background(scene_.lights), caustics(caustics_) {
  for (const SunLight& sun : scene.lights.suns) suns.emplace_back(sun);
  settings.sample_sky = settings.sample_sky && !background.empty();
  layout.lights = int(scene.lights.suns.size() + scene.lights.rects.size()) + (settings.sample_sky ? 1 : 0);
}

Eigen::Vector3f offsetFromSurface(const Eigen::Vector3f& p, const Eigen::Vector3f& n) {
  return p + (1e-4f * (1.0f + p.cwiseAbs().maxCoeff())) * n;
}

namespace {

// One camera path: the state it carries from vertex to vertex and the steps it takes (pbrt-v4's VolPathIntegrator::Li
// laid out as named steps). trace() is the loop; light sampling (next-event estimation) lives in its own steps below.
class Path {
 public:
  Path(const PathContext& context, const Ray& ray, const CameraSample& camera, const PixelSampler& sampler,
       std::uint32_t sample)
      : context_(context),
        scene_(context.scene),
        lights_(context.scene.lights),
        layout_(context.layout),
        camera_(camera),
        sampler_(sampler),
        sample_(sample),
        camera_ray_(ray),
        time_(ray.time),
        ray_(ray),
        previous_sampled_sky_(context.settings.sample_sky),
        caustics_(context.caustics ? &context.caustics->forSample(sample) : nullptr) {}

  PathResult trace();

 private:
  using Branch = CameraSample::Branch;
  enum class Step { Next, Stop, Shade };  // go on with the new ray / end the path / shade the surface hit

  // What a non-specular surface vertex needs to weigh the light it reflects.
  struct SurfaceVertex {
    const Bsdf& bsdf;
    Eigen::Vector3f ns;
    Color base, prefix;  // prefix: throughput of the specular prefix, if this is the first non-specular vertex
    bool first, continues;
    float q;  // the chance of continuing (Russian roulette)
  };

  // Steps of the loop.
  Step travelMedium(int vertex, const std::optional<SurfaceHit>& hit);
  void addLightsPassed(int vertex, const std::optional<SurfaceHit>& hit);
  void addEscapedLight(int vertex);
  Step crossInterface(int vertex, const SurfaceHit& hit, const Material& material, Branch branch);
  Step scatterAtSurface(int vertex, SurfaceHit& hit, const Material& material);
  Color surfaceBaseColor(int vertex, SurfaceHit& hit, const Material& material) const;

  // Light sampling.
  template <class Use>
  int sampleLights(int vertex, const Eigen::Vector3f& origin, const Eigen::Vector3f& n, const Use& use) const;
  void sampleLightsAtInterface(int vertex, const SurfaceHit& hit, const DielectricBsdf& bsdf, const Eigen::Vector3f& n,
                               bool continues);
  int sampleLightsAtSurface(int vertex, const SurfaceHit& hit, const SurfaceVertex& v, const Eigen::Vector3f& origin,
                            const Eigen::Vector3f& ng);
  void sampleSkyAtSurface(int vertex, int light_index, const SurfaceHit& hit, const SurfaceVertex& v,
                          const Eigen::Vector3f& origin, const Eigen::Vector3f& ng);
  void reflect(int vertex, const SurfaceVertex& v, const Eigen::Vector3f& wi, const Color& incoming);
  void gatherCaustics(int vertex, const SurfaceHit& hit, const SurfaceVertex& v, const Eigen::Vector3f& ng);

  // The path's throughput and the light it has gathered.
  void weigh(const Color& w) {
    t_diffuse_ = t_diffuse_.cwiseProduct(w);
    t_other_ = t_other_.cwiseProduct(w);
  }
  // Light arriving along the path's current ray; `indirect` as in add().
  void arrive(const Color& light, bool indirect) {
    add(t_diffuse_.cwiseProduct(light), t_other_.cwiseProduct(light), indirect);
  }
  // A contribution to the two parts: `diffuse` before the first non-specular vertex's base colour multiplies it.
  // Indirect light (found after the path's first scattering vertex, as Cycles counts bounces) is clamped: the
  // contribution to the pixel is scaled down, hue kept, until its mean over R, G, B is at most clamp_indirect.
  void add(Color diffuse, Color other, bool indirect) {
    const float limit = context_.settings.clamp_indirect;
    if (indirect && limit > 0) {
      const float mean = (first_base_.cwiseProduct(diffuse) + other).cwiseAbs().sum() / 3.0f;
      if (mean > limit) {
        diffuse *= limit / mean;
        other *= limit / mean;
      }
    }
    diffuse_ += diffuse;
    other_ += other;
  }
  bool dark() const { return t_diffuse_.isZero() && t_other_.isZero(); }
  // Every ray of the path is traced at the camera ray's instant (motion blur).
  Ray atTime(Ray r) const {
    r.time = time_;
    return r;
  }
  // The guides' position of a vertex met through smooth interfaces: its virtual image, as far along the camera ray
  // as the path has come (a reflection's image lies behind the mirror, never behind the camera).
  Eigen::Vector3f guidePosition(const Eigen::Vector3f& p, float t) const {
    return travelled_ == 0 ? p : Eigen::Vector3f(camera_ray_.at(travelled_ + t));
  }

  const PathContext& context_;
  const Scene& scene_;
  const Lights& lights_;
  const SampleLayout& layout_;
  const CameraSample& camera_;
  const PixelSampler& sampler_;
  const std::uint32_t sample_;
  const Ray camera_ray_;
  const float time_;

  PathResult result_;
  Ray ray_;
  float travelled_ = 0;  // along the camera ray's unfolded specular chain (guidePosition)
  // Light reaching the camera is summed in two parts, split at the first non-specular vertex (the first surface,
  // unless the path first passes smooth gelatine) by the lobe it leaves by: `diffuse` (divided by that surface's
  // base colour) and `other` (coat, gelatine, and sky seen directly or through gelatine). t_diffuse and t_other are
  // the path's throughput beyond that vertex in those two parts; before it t_other is the throughput of the
  // specular prefix (the smooth interfaces and the absorption met so far).
  Color diffuse_ = Color::Zero(), other_ = Color::Zero();
  Color t_diffuse_ = Color::Zero(), t_other_ = Color::Ones();
  Color first_base_ = Color::Zero();
  bool split_ = false;      // the first non-specular vertex is behind
  float previous_pdf_ = 0;  // density of the BSDF sample that made this ray; 0 for the camera ray
  // What the vertex that made this ray sampled itself, so that a light this ray finds is weighted against it (MIS)
  // or, where that vertex could not sample it (a smooth interface, a scattering event), counted fully.
  bool previous_sampled_lights_ = true, previous_sampled_sky_;
  int leaving_ = -1;                  // the surface the current ray starts on (none for the camera ray)
  const Material* medium_ = nullptr;  // the gelatine the current ray travels through
  int bounce_ = 0;                    // continuations from surfaces (max_bounces counts them)
  int interface_events_ = 0, scatter_events_ = 0;
  // Caustics: whether the last surface vertex read the caustic photon map, and how many smooth interfaces the path
  // crossed since it with nothing else between: a sun found so is the map's light, not the path's.
  const CausticMap* caustics_;  // this sample's map, or none
  bool caustic_receiver_ = false;
  int chain_interfaces_ = 0;
};

PathResult Path::trace() {
  for (int vertex = 0;; ++vertex) {
    // Find the next surface.
    ++result_.rays;
    auto hit = scene_.intersect(ray_, leaving_);
    // Inside gelatine: absorption on the way, or a scattering event before the surface.
    if (medium_) {
      const Step step = travelMedium(vertex, hit);
      if (step == Step::Stop) break;
      if (step == Step::Next) continue;
    }
    // Emitters the ray passes or escapes to.
    addLightsPassed(vertex, hit);
    if (!hit) {
      addEscapedLight(vertex);
      break;
    }
    if (vertex == 0) result_.velocity = hit->dpdt;  // the guides' point: the first hit (tracePathSplit too)
    // Gelatine's clear interface, unless its print layer is drawn; else a surface with a BSDF.
    const Material& material = scene_.material(hit->material);
    const Branch branch = vertex == 0 && material.dielectric ? camera_.branch : Branch::Drawn;
    if (vertex == 0 && material.dielectric) result_.gelatine_first = true, result_.print = material.print;
    const bool printed =
        branch == Branch::Drawn
            ? material.print > 0 && sampler_.get1D(sample_, SampleLayout::print(vertex)) < material.print
            : branch == Branch::Print;
    const Step step = material.dielectric && !printed ? crossInterface(vertex, *hit, material, branch)
                                                      : scatterAtSurface(vertex, *hit, material);
    if (step == Step::Stop) break;
  }
  // The two parts, the diffuse one modulated by the first surface's base colour.
  result_.diffuse = first_base_.cwiseProduct(diffuse_);
  result_.diffuse_demodulated = luminance(diffuse_);
  result_.radiance = result_.diffuse + other_;
  return result_;
}

// Beer-Lambert absorption to the next surface or, in a scattering medium, to a collision drawn on the way (then an
// isotropic phase function: the throughput times the albedo, a new direction drawn uniformly).
Path::Step Path::travelMedium(int vertex, const std::optional<SurfaceHit>& hit) {
  const Material& medium = *medium_;
  const float t_hit = hit ? hit->t : std::numeric_limits<float>::infinity();
  float t = t_hit;
  if (medium.scatter > 0) {
    t = std::min(t_hit, medium.freeFlight(sampler_.get1D(sample_, SampleLayout::medium(vertex))));
  }
  if (!hit && t == t_hit) {  // left through an open surface: no longer inside anything
    medium_ = nullptr;
    return Step::Shade;
  }
  weigh(medium.transmittance(t));
  if (!(t < t_hit)) return Step::Shade;
  weigh(medium.scatter_albedo);
  const Eigen::Vector3f p = ray_.at(t);
  if (!split_) {
    split_ = true, result_.hit = true;
    result_.albedo = first_base_ = t_other_;
    result_.normal = -ray_.direction, result_.position = guidePosition(p, t);
    t_diffuse_ = Color::Zero();
  }
  if (++scatter_events_ > kMaxScatterEvents || dark()) return Step::Stop;
  const Eigen::Vector2f u = sampler_.get2D(sample_, layout_.bsdfDirection(vertex));
  const float z = 1.0f - 2.0f * u.x(), r = std::sqrt(std::max(0.0f, 1.0f - z * z));
  const Eigen::Vector2f phi = cosSin2Pi(u.y());
  travelled_ += t;
  ray_ = atTime(Ray{p, Eigen::Vector3f(r * phi.x(), r * phi.y(), z)});
  previous_pdf_ = 1.0f / (4.0f * std::numbers::pi_v<float>);
  previous_sampled_lights_ = previous_sampled_sky_ = false;  // lights are outside: a shadow ray from here is
  leaving_ = -1;                                             // always blocked by the body's own surface
  caustic_receiver_ = false;                                 // not a specular chain: the path's own light
  return Step::Next;
}

// A continuation may pass an area light: counted fully where the vertex that made it could not sample lights, else
// weighted against that vertex's light sample (MIS).
void Path::addLightsPassed(int vertex, const std::optional<SurfaceHit>& hit) {
  const bool lights_weighed = previous_sampled_lights_;
  if (vertex == 0 || !(context_.settings.mis || !lights_weighed)) return;
  const float tmax = hit ? hit->t : ray_.tfar;
  for (const RectLight& rect : lights_.rects) {
    const LightHit h = rectAlongRay(rect, ray_.origin, ray_.direction, tmax);
    if (h.pdf > 0) arrive(h.radiance * (lights_weighed ? powerHeuristic(previous_pdf_, h.pdf) : 1.0f), vertex > 1);
  }
}

// An escaped ray: the sky (weighted against its light sample where one was taken) and any sun disc it points into.
// Camera rays see the sky only.
void Path::addEscapedLight(int vertex) {
  const bool lights_weighed = previous_sampled_lights_;
  Color light = context_.background.eval(ray_.direction);
  if (vertex > 0) {
    if (context_.settings.sample_sky && previous_sampled_sky_)
      light *= powerHeuristic(previous_pdf_, context_.background.pdf(ray_.direction));
    // Through smooth gelatine alone from a surface that read the caustic map, the suns are the map's light.
    const bool caustic = caustic_receiver_ && chain_interfaces_ > 0;
    if (!caustic)
      for (const SunCone& sun : context_.suns) {
        const LightHit h = sunInDirection(sun, ray_.direction);
        if (h.pdf > 0 && (context_.settings.mis || !lights_weighed))
          light += h.radiance * (lights_weighed ? powerHeuristic(previous_pdf_, h.pdf) : 1.0f);
      }
  }
  arrive(light, vertex > 1);  // found by the ray leaving vertex - 1
}

// Gelatine's clear interface: reflect or refract (the branch asked for at the camera ray, else one drawn), entering
// or leaving the medium. A rough interface samples the lights; a smooth one cannot.
Path::Step Path::crossInterface(int vertex, const SurfaceHit& hit, const Material& material, Branch branch) {
  const InterfaceCrossing crossing(hit, ray_.direction);
  const Eigen::Vector3f &wo = crossing.wo, &outward = crossing.outward, &n = crossing.n;
  const bool entering = crossing.entering;
  const DielectricBsdf bsdf = crossing.bsdf(material.ior, material.roughness);
  // The guides: this interface, unless a non-specular vertex follows.
  if (vertex == 0)
    result_.front_normal = entering ? outward : Eigen::Vector3f(-outward), result_.front_position = hit.p;
  if (!split_) {
    result_.hit = true;
    result_.albedo = t_other_;
    result_.normal = entering ? outward : Eigen::Vector3f(-outward);
    result_.position = guidePosition(hit.p, hit.t);
    if (!bsdf.smooth()) split_ = true, first_base_ = t_other_, t_diffuse_ = Color::Zero();
  }
  const bool continues = ++interface_events_ <= kMaxInterfaceEvents;
  if (!bsdf.smooth()) sampleLightsAtInterface(vertex, hit, bsdf, n, continues);
  if (bsdf.smooth()) ++chain_interfaces_;
  else caustic_receiver_ = false;  // a rough interface: not a chain the photons follow
  if (!continues) return Step::Stop;
  // Reflect or refract.
  float u_lobe = sampler_.get1D(sample_, layout_.bsdfLobe(vertex));
  if (bsdf.smooth() && branch != Branch::Drawn) {  // the branch asked for: below or above the reflectance
    result_.reflectance = fresnelDielectric(std::abs(n.dot(wo)), entering ? material.ior : 1 / material.ior);
    u_lobe = branch == Branch::Reflect ? 0.0f : std::nextafter(1.0f, 0.0f);
  }
  const Eigen::Vector2f u = sampler_.get2D(sample_, layout_.bsdfDirection(vertex));
  const auto s = bsdf.sample(u_lobe, u.x(), u.y());
  if (!s) return Step::Stop;
  const std::optional<Ray> next = crossing.leave(hit, *s);
  if (!next) return Step::Stop;
  weigh(Color::Constant(s->weight));
  if (dark()) return Step::Stop;
  if (s->transmitted) medium_ = entering ? &material : nullptr;
  previous_pdf_ = s->pdf;
  previous_sampled_lights_ = !bsdf.smooth();
  previous_sampled_sky_ = false;
  travelled_ += hit.t;
  ray_ = *next;
  leaving_ = hit.shape;
  return Step::Next;
}

// A surface with a BSDF (diffuse, coat, or gelatine's print layer): the guides if it is the first non-specular
// vertex, light samples, then a continuation drawn from the BSDF (Russian roulette from the second on).
Path::Step Path::scatterAtSurface(int vertex, SurfaceHit& hit, const Material& material) {
  const Eigen::Vector3f wo = -ray_.direction;
  const bool first = !split_;
  // Two-sided shading: turn both normals to the side the ray came from.
  const Eigen::Vector3f ng = hit.ng.dot(wo) >= 0 ? hit.ng : Eigen::Vector3f(-hit.ng);
  Eigen::Vector3f ns = hit.ns.dot(ng) >= 0 ? hit.ns : Eigen::Vector3f(-hit.ns);
  if (ns.dot(wo) <= 0) ns = ng;  // interpolated normal facing away from the viewer: shade flat instead of black
  const Color base = surfaceBaseColor(vertex, hit, material);
  const Color prefix = first ? t_other_ : Color::Ones();  // throughput of the specular prefix, if any
  // The guides.
  if (first) {
    split_ = true;
    result_.hit = true;
    result_.albedo = first_base_ = prefix.cwiseProduct(base);
    result_.normal = ns;
    result_.position = guidePosition(hit.p, hit.t);
  }
  const Bsdf bsdf(material, base, ns, wo);
  const Eigen::Vector3f origin = offsetFromSurface(hit.p, ng);
  const bool continues = bounce_ < context_.settings.max_bounces;
  // The chance of continuing from here: 1 for the first continuation; with Russian roulette, from the second on,
  // the path's throughput so far (its largest channel, at most 1), as pbrt-v4: paths that carry little light stop
  // early, and the survivors' weight / q stays near 1, so the roulette adds little noise. The BSDF strategy's
  // density as MIS sees it is what BSDF sampling draws times q.
  float q = continues ? 1.0f : 0.0f;
  if (continues && bounce_ > 0 && context_.settings.roulette)
    q = std::clamp((first_base_.cwiseProduct(t_diffuse_) + t_other_).maxCoeff(), kMinContinuation, 1.0f);
  const SurfaceVertex v{bsdf, ns, base, prefix, first, continues, q};

  // Light samples: suns and area lights; the sky only where a continuation follows (it is reached by them only).
  const int light_index = sampleLightsAtSurface(vertex, hit, v, origin, ng);
  const bool receiver = caustics_ && !material.dielectric;
  if (receiver) gatherCaustics(vertex, hit, v, ng);
  if (!continues) return Step::Stop;
  if (context_.settings.sample_sky) sampleSkyAtSurface(vertex, light_index, hit, v, origin, ng);

  // Russian roulette, then the continuation.
  if (q < 1 && sampler_.get1D(sample_, layout_.roulette(vertex)) >= q) return Step::Stop;
  const float u_lobe = sampler_.get1D(sample_, layout_.bsdfLobe(vertex));
  const Eigen::Vector2f u = sampler_.get2D(sample_, layout_.bsdfDirection(vertex));
  const auto s = bsdf.sample(u_lobe, u.x(), u.y());
  if (!s || s->wi.dot(ng) <= 0) return Step::Stop;  // absorbed, or headed into the surface it left
  if (first) {
    t_diffuse_ = Color::Constant(s->lobes.diffuse / q);
    t_other_ = prefix * (s->lobes.specular / q);
  } else {
    t_diffuse_ = t_diffuse_.cwiseProduct(s->weight) / q;
    t_other_ = t_other_.cwiseProduct(s->weight) / q;
  }
  if (dark()) return Step::Stop;
  previous_pdf_ = q * s->pdf;
  previous_sampled_lights_ = context_.settings.light_samples;
  previous_sampled_sky_ = context_.settings.sample_sky;
  caustic_receiver_ = receiver;
  chain_interfaces_ = 0;
  ray_ = atTime(Ray{origin, s->wi});
  leaving_ = hit.shape;
  ++bounce_;
  return Step::Next;
}

// The surface's base colour: at the camera ray's hit, a textured one averaged over the pixel's footprint (widened by
// the motion over the shutter); elsewhere point-sampled.
Color Path::surfaceBaseColor(int vertex, SurfaceHit& hit, const Material& material) const {
  if (vertex != 0 || !material.texture) return material.baseColor(hit.uv);
  scene_.uvDerivatives(hit);
  TextureFootprint f = footprint(ray_, camera_.camera, hit);
  f.jitter = sampler_.get2D(sample_, SampleLayout::kTexture);
  Eigen::Vector2f centre = hit.uv - camera_.offset.x() * f.duvdx - camera_.offset.y() * f.duvdy;
  if (camera_.camera) blurFootprint(f, centre, ray_, *camera_.camera, hit);
  return material.baseColor(centre.allFinite() ? centre : hit.uv, f);
}

// One sample of every sun and area light seen from origin above the normal n, each from its own slot, handed to
// use(LightSample); returns the next slot's light index.
template <class Use>
int Path::sampleLights(int vertex, const Eigen::Vector3f& origin, const Eigen::Vector3f& n, const Use& use) const {
  int light_index = 0;
  for (const SunCone& sun : context_.suns) {
    const Eigen::Vector2f u = sampler_.get2D(sample_, layout_.light(vertex, light_index++));
    use(sampleSun(sun, origin, n, u.x(), u.y()));
  }
  for (const RectLight& rect : lights_.rects) {
    const Eigen::Vector2f u = sampler_.get2D(sample_, layout_.light(vertex, light_index++));
    use(sampleRect(rect, origin, n, u.x(), u.y()));
  }
  return light_index;
}

// A rough interface: suns and area lights outside, seen by reflection or transmission.
void Path::sampleLightsAtInterface(int vertex, const SurfaceHit& hit, const DielectricBsdf& bsdf,
                                   const Eigen::Vector3f& n, bool continues) {
  const Eigen::Vector3f& outward = hit.ng;
  const Eigen::Vector3f origin = offsetFromSurface(hit.p, outward);
  sampleLights(vertex, origin, outward, [&](const LightSample& s) {
    if (s.value.isZero()) return;
    const float f = bsdf.eval(s.wi);
    if (!(f > 0)) return;
    ++result_.rays;
    if (!unoccluded(scene_, atTime(s.shadow), hit.shape)) return;
    const bool combined = continues && s.pdf > 0 && context_.settings.mis;
    const float weight = combined ? powerHeuristic(s.pdf, bsdf.pdf(s.wi)) : 1.0f;
    arrive(s.value * (f * std::abs(n.dot(s.wi)) * weight), vertex > 0);
  });
}

// Suns and area lights at a surface, weighted against the BSDF's continuation (MIS); with no continuation from here
// light samples are the only strategy: full weight. Returns the next slot's light index (the sky's).
int Path::sampleLightsAtSurface(int vertex, const SurfaceHit& hit, const SurfaceVertex& v,
                                const Eigen::Vector3f& origin, const Eigen::Vector3f& ng) {
  return sampleLights(vertex, origin, ng, [&](const LightSample& s) {
    if (!context_.settings.light_samples || s.value.isZero() || v.ns.dot(s.wi) <= 0) return;
    ++result_.rays;
    if (!unoccluded(scene_, atTime(s.shadow), hit.shape)) return;
    const bool combined = v.continues && s.pdf > 0 && context_.settings.mis;
    const float weight = combined ? powerHeuristic(s.pdf, v.q * v.bsdf.pdf(s.wi)) : 1.0f;
    reflect(vertex, v, s.wi, s.value * weight);
  });
}

// The sky (or environment map) at a surface, weighted against the BSDF's continuation (MIS).
void Path::sampleSkyAtSurface(int vertex, int light_index, const SurfaceHit& hit, const SurfaceVertex& v,
                              const Eigen::Vector3f& origin, const Eigen::Vector3f& ng) {
  const Eigen::Vector2f u = sampler_.get2D(sample_, layout_.light(vertex, light_index));
  float pdf = 0;
  const Eigen::Vector3f wi = context_.background.sample(u.x(), u.y(), pdf);
  if (!(pdf > 0 && wi.dot(ng) > 0 && v.ns.dot(wi) > 0)) return;
  ++result_.rays;
  if (unoccluded(scene_, atTime(Ray{origin, wi}), hit.shape))
    reflect(vertex, v, wi, context_.background.eval(wi) * (powerHeuristic(pdf, v.q * v.bsdf.pdf(wi)) / pdf));
}

// Light arriving at a surface vertex from direction wi, already divided by its sampling density and weighted
// (a light sample: indirect beyond the path's first vertex).
void Path::reflect(int vertex, const SurfaceVertex& v, const Eigen::Vector3f& wi, const Color& incoming) {
  const BsdfLobes f = v.bsdf.evalLobes(wi);
  const float cos_i = v.ns.dot(wi);
  if (v.first) {
    add((f.diffuse * cos_i) * incoming, v.prefix.cwiseProduct((f.specular * cos_i) * incoming), vertex > 0);
  } else {
    arrive(((f.diffuse * cos_i) * v.base.array() + f.specular * cos_i).matrix().cwiseProduct(incoming), vertex > 0);
  }
}

// The caustic photons around the vertex (caustic_photons.h), through its BSDF: sum f(wi) power kernel, light at this
// vertex like its light samples'.
void Path::gatherCaustics(int vertex, const SurfaceHit& hit, const SurfaceVertex& v, const Eigen::Vector3f& ng) {
  caustics_->gather(hit.p, ng, [&](const Eigen::Vector3f& wi, const Color& irradiance) {
    const float cos_i = v.ns.dot(wi);
    if (cos_i > 0) reflect(vertex, v, wi, irradiance / cos_i);
  });
}

}  // namespace

PathResult tracePath(const PathContext& context, Ray ray, const CameraSample& camera, const PixelSampler& sampler,
                     std::uint32_t sample) {
  return Path(context, ray, camera, sampler, sample).trace();
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
  sum.gelatine_first = true, sum.print = c, sum.reflectance = f;
  const auto add = [&](const PathResult& r, float w) {
    sum.radiance += w * r.radiance;
    sum.diffuse += w * r.diffuse;
    sum.diffuse_demodulated += w * r.diffuse_demodulated;
    sum.albedo += w * r.albedo;
    sum.rays += r.rays;
  };
  add(first, interface_weight);
  sum.through = interface_weight * first.radiance;
  for (const Part& part : others)
    if (part.weight > 0) {
      camera.branch = part.branch;
      add(tracePath(context, ray, camera, sampler, sample), part.weight);
    }
  // The geometric guides are the gelatine's surface: what lies behind it (the far side's print or the floor through
  // it, each branch's first non-specular vertex) changes from sample to sample, and guides that jump between them
  // keep the denoiser from mixing neighbouring pixels at all.
  sum.hit = true;
  sum.normal = first.front_normal, sum.position = first.front_position;
  sum.front_normal = first.front_normal, sum.front_position = first.front_position;
  sum.velocity = first.velocity;
  return sum;
}

bool unoccluded(const Scene& scene, const Ray& shadow, int leaving) { return !scene.occluded(shadow, leaving); }

}  // namespace wobble::render
