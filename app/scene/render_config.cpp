// Readers of the render-related scene keys (render_config.h): same TableReader checks as every other key.
#include "app/scene/render_config.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "render/renderer.h"

#include "app/scene/body_kinds.h"
#include "app/scene/collider_kinds.h"
#include "app/scene/material_kinds.h"
#include "app/scene/scene_file.h"
#include "app/scene/table_reader.h"

namespace wobble {
namespace {

Vec3 readColor(TableReader& r, const Vec3& fallback) {
  const Vec3 c = r.vec3("color", fallback);
  if ((c.array() < 0).any() || (c.array() > 1).any()) r.fail("color", "each component must be in [0, 1] (linear RGB)");
  return c;
}

std::array<int, 2> readResolution(TableReader& r, std::array<int, 2> fallback) {
  const auto wh = r.pair("resolution", {double(fallback[0]), double(fallback[1])}, Range{2, 16384});
  if (wh[0] != std::floor(wh[0]) || wh[1] != std::floor(wh[1]))
    r.fail("resolution", "must be two whole numbers [width, height] in [2, 16384]");
  return {int(wh[0]), int(wh[1])};
}

// Chosen from `wobble study render` on the shipped scenes (docs/rendering.md, "Quality presets"). One denoised sample
// per pixel already has a several times lower error than the old eight noisy ones; a higher --spp turns on adaptive
// sampling (noise threshold 0.1: at 16 spp, the error of 16 everywhere for a third of the samples).
constexpr QualityPreset kPresets[] = {
    {"preview", 1, 1, 0.1, true, 0.5, "half resolution, 1 sample per pixel, denoised: to check a run's motion"},
    {"final", 1, 1, 0.1, true, 1.0,
     "full resolution, denoised, the scene's render.samples (1 if unset): a video's quality, not a converged still; "
     "for a still that converges give --spp N (N samples at most, its noise threshold following N)"},
};

}  // namespace

double autoNoiseThreshold(int samples) { return std::max(0.001, 1.0 / std::max(1, samples)); }

const QualityPreset& qualityPreset(const std::string& name) {
  for (const QualityPreset& p : kPresets)
    if (name == p.name) return p;
  throw std::out_of_range("no quality preset '" + name + "'");
}

std::vector<std::string> qualityNames() {
  std::vector<std::string> names;
  for (const QualityPreset& p : kPresets) names.emplace_back(p.name);
  return names;
}

render::RenderSettings renderSettings(const RenderOptionsConfig& o, int frame) {
  render::RenderSettings s;
  s.samples_per_pixel = o.samples_per_pixel;
  s.min_samples = o.min_samples;
  s.noise_threshold = static_cast<float>(o.noise_threshold);
  s.max_bounces = o.bounces;
  render::parseSamplerKind(o.sampler, s.sampler);  // checked when read
  s.sample_sky = o.sky_sampling;
  s.roulette = o.russian_roulette;
  s.clamp_indirect = static_cast<float>(o.clamp_indirect);
  s.caustics.photons = o.caustics == "photons" ? o.caustic_photons : 0;
  s.caustics.radius = static_cast<float>(o.caustic_radius);
  s.frame = static_cast<std::uint32_t>(frame);  // the noise seed: the same frame is the same image
  return s;
}

void readBodyLook(TableReader& r, const BodyKind& kind, const std::string& name, SceneFile& scene) {
  BodyLook look;
  const bool textured = scene.textures.count(name) > 0;
  // Textured: white, so the texture shows its own colours.
  look.color = readColor(r, textured ? Vec3(1, 1, 1) : kind.color);
  look.textured = textured;
  look.material = r.string("material", std::string(kind.material), materialTypes());
  const MaterialKind& material = materialKind(look.material);
  if (material.closed_only && !kind.closed)
    r.fail("material", "\"" + look.material + "\" needs a closed surface with an inside (a jelly), not a " +
                           std::string(kind.type));
  if (material.read) material.read(r, look);
  scene.render.bodies[name] = look;
}

void readColliderLook(TableReader& r, const ColliderKind& kind, const std::string& name, ColliderLook look,
                      SceneFile& scene) {
  look.type = kind.type;
  look.color = readColor(r, kind.color);
  look.texture = r.string("texture", std::string(kind.texture), {"none", "checker", "wood"});
  if (kind.read_look) kind.read_look(r, look);
  scene.render.colliders[name] = look;
}

void readRenderTables(TableReader& root, SceneFile& scene) {
  TableReader c = root.child("camera");
  CameraConfig& cam = scene.render.camera;
  if (c.node("position")) cam.position = c.vec3("position", Vec3::Zero());
  if (c.node("look_at")) cam.look_at = c.vec3("look_at", Vec3::Zero());
  cam.up = c.vec3("up", cam.up);
  cam.fov_deg = c.number("fov", cam.fov_deg, Range{0, 180, true, true});
  cam.resolution = readResolution(c, cam.resolution);
  cam.follow = c.string("follow", "");
  cam.follow_smoothing = c.number("follow_smoothing", cam.follow_smoothing, Range::nonNegative());
  if (cam.position && cam.look_at && (*cam.position - *cam.look_at).norm() == 0)
    c.fail("look_at", "must differ from camera.position");
  if (cam.up.norm() == 0) c.fail("up", "must not be zero");
  const Vec3 view = cam.look_at.value_or(Vec3::Zero()) - cam.position.value_or(Vec3(0, 0, 1));
  if (cam.position && cam.look_at && view.cross(cam.up).norm() < 1e-9 * view.norm() * cam.up.norm())
    c.fail("up", "must not be parallel to the view direction (look_at - position)");
  if (!cam.follow.empty() && !scene.render.bodies.count(cam.follow)) {
    std::string list;
    for (const auto& [body, look] : scene.render.bodies) list += (list.empty() ? "" : ", ") + body;
    c.fail("follow", "must name a body of the scene: " + list);
  }
  cam.aperture = c.number("aperture", cam.aperture, Range::nonNegative());
  cam.shutter = c.number("shutter", cam.shutter, Range::unit());
  if (const toml::node* focus = c.node("focus")) {
    if (focus->is_string()) {
      if (cam.follow.empty() || focus->as_string()->get() != cam.follow)
        c.fail("focus", "must be a distance > 0 (m) or the name of the followed body (camera.follow" +
                            (cam.follow.empty() ? std::string(" is not set)") : " = \"" + cam.follow + "\")"));
      cam.focus_follow = true;
    } else {
      cam.focus = c.number("focus", 0, Range::positive());
    }
  }
  c.finish();

  // A scene renders only if it asks to: no [render] table, no frames (unless a flag that sets a render.* key, such as
  // --render png or --spp, creates it).
  const bool asks = root.table("render") != nullptr;
  TableReader r = root.child("render");
  RenderOptionsConfig& o = scene.render.options;
  o.png = r.boolean("png", asks);
  o.exr = r.boolean("exr", o.exr);
  o.video = r.boolean("video", o.video);
  o.quality = r.string("quality", o.quality, qualityNames());
  const QualityPreset& preset = qualityPreset(o.quality);
  o.samples_per_pixel = r.integer("samples", preset.samples_per_pixel, Range{1, 65536});
  o.min_samples = r.integer("min_samples", std::min(preset.min_samples, o.samples_per_pixel), Range{1, 65536});
  if (o.min_samples > o.samples_per_pixel)
    r.fail("min_samples", "must be at most render.samples (" + std::to_string(o.samples_per_pixel) + ")");
  const toml::node* threshold = r.node("noise_threshold");
  if (threshold && threshold->is_string()) {
    if (threshold->as_string()->get() != "auto") r.fail("noise_threshold", "must be a number in [0, 1] or \"auto\"");
    o.noise_threshold = autoNoiseThreshold(o.samples_per_pixel);
  } else {
    o.noise_threshold = r.number("noise_threshold", preset.noise_threshold, Range{0, 1});
  }
  o.denoise = r.boolean("denoise", preset.denoise);
  o.sampler = r.string("sampler", o.sampler, {"sobol", "independent"});
  o.environment = readEnvironment(r, scene);  // sampled by default: an HDR map's sun is found by light samples
  o.sky_sampling = r.boolean("sky_sampling", o.environment.named());
  o.russian_roulette = r.boolean("russian_roulette", o.russian_roulette);
  o.clamp_indirect = r.number("clamp_indirect", o.clamp_indirect, Range{0, 1e6});
  o.caustics = r.string("caustics", o.caustics, {"photons", "off"});
  o.caustic_photons = r.integer("caustic_photons", o.caustic_photons, Range{1000, 100000000});
  o.caustic_radius = r.number("caustic_radius", o.caustic_radius, Range{0.001, 10});
  o.bounces = r.integer("bounces", o.bounces, Range{0, 16});
  o.exposure = r.number("exposure", o.exposure, Range{-20, 20});
  o.sun_direction = r.vec3("sun_direction", o.sun_direction);
  if (o.sun_direction.norm() == 0) r.fail("sun_direction", "must not be zero");
  o.sun_radius_deg = r.number("sun_radius_deg", o.sun_radius_deg, Range{0, 45});
  if (o.video && !o.png) r.fail("video", "needs PNG frames: set render.png = true (or --render png)");
  r.finish();
  // The preset's resolution scale, kept even (the video's yuv420p needs even sizes) and at least 2.
  if (preset.resolution_scale != 1)
    for (int& size : cam.resolution) size = std::max(2, 2 * int(std::lround(size * preset.resolution_scale / 2)));
}

}  // namespace wobble
