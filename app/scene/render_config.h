// What a scene says about its pictures: the [camera] and [render] tables, and the look of each body (`color`,
// `material`) and collider (`color`, `texture`, `texture_scale`). Read with the rest of the scene (scene.cpp calls
// the readers below), so these keys get the same type, range and unknown-key checks; scenes/README.md documents them.
// Values stay in double here, like the scene; the renderer's floats are made in render_scene.cpp.
#pragma once
#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "app/scene/environment_config.h"
#include "sim/types.h"

namespace wobble {

class TableReader;
struct SceneFile;
struct BodyKind;
struct ColliderKind;

struct CameraConfig {
  // Unset position/look_at: framed automatically around the bodies and finite colliders at t = 0 (camera_rig.h).
  std::optional<Vec3> position, look_at;
  Vec3 up = Vec3::UnitY();
  double fov_deg = 40;  // vertical
  std::array<int, 2> resolution{1280, 720};
  std::string follow;             // body name, or empty: a fixed camera
  double follow_smoothing = 0.5;  // s: time constant of the exponential smoothing of the followed centroid
  double aperture = 0;            // thin-lens radius (m); 0: a pinhole
  double focus = 0;               // distance of the plane in focus (m); 0: the look_at point's
  bool focus_follow = false;      // focus on the followed body (its smoothed centroid) instead
  double shutter = 0;             // fraction of the frame interval the shutter is open (motion blur); 0: off
};

// A quality preset: the sampling and denoising settings a `render.quality` name stands for. Each can still be set
// on its own (an explicit key or flag wins over the preset). Chosen from `wobble study render` (docs/studies.md).
struct QualityPreset {
  const char* name;
  int samples_per_pixel;   // the most
  int min_samples;         // adaptive sampling's first pass
  double noise_threshold;  // 0: no adaptive sampling
  bool denoise;
  double resolution_scale;  // of camera.resolution (preview: half each way, a quarter of the pixels)
  const char* summary;      // for --help and the docs
};
const QualityPreset& qualityPreset(const std::string& name);  // "preview" or "final"; throws std::out_of_range
// render.noise_threshold = "auto" (what --spp sets): Cycles' automatic threshold for a budget of `samples`,
// max(0.001, 1 / samples), so more samples buy a lower error instead of stopping where a fixed threshold says.
double autoNoiseThreshold(int samples);
std::vector<std::string> qualityNames();

struct RenderOptionsConfig {
  bool png = true, exr = false, video = false;
  std::string quality = "final";
  int samples_per_pixel = 0;  // the most; these four come from the quality preset unless set
  int min_samples = 0;
  double noise_threshold = 0;
  bool denoise = true;
  std::string sampler = "sobol";  // "sobol" or "independent" (render/sampler.h)
  bool sky_sampling = false;
  bool russian_roulette = false;     // from the second bounce on, by throughput (render/path_tracer.h)
  double clamp_indirect = 10;        // Cycles' default (render/path_tracer.h); 0: off
  std::string caustics = "photons";  // "photons": a caustic photon map (render/caustic_photons.h); "off"
  int caustic_photons = 100000;      // per sun per map (render/caustic_photons.h)
  double caustic_radius = 0.1;       // m: the density estimate's kernel
  int bounces = 2;
  double exposure = -0.5;                // stops: the sun and sky on a light surface need a little less than 0
  Vec3 sun_direction{-0.35, 1.0, 0.55};  // towards the sun
  double sun_radius_deg = 2.0;           // apparent radius: the softness of shadows
  EnvironmentConfig environment;         // named: it lights the scene instead of the sky and the sun
};

// A gelatine body's own keys (material_kinds.cpp; render/dielectric.h).
struct GelatineLook {
  double ior = 1.4, roughness = 0;
  Vec3 absorption_color{0.85, 0.35, 0.4};  // white light's colour after absorption_depth metres inside
  double absorption_depth = 1;
  double scatter = 0;  // mean free path between scattering events (m); 0: clear
  Vec3 scatter_albedo{1, 1, 1};
  double print = 0.5;  // coverage of the printed skin (texture x color); 0 without a texture
};

struct BodyLook {
  Vec3 color{1, 1, 1};
  std::string material = "jelly";  // a material kind (material_kinds.h): "jelly", "diffuse", "gelatine"
  bool textured = false;
  GelatineLook gelatine;
};

struct ColliderLook {
  std::string type;  // the collider's kind (collider_kinds.h), which draws it
  Vec3 color{0.7, 0.7, 0.7};
  std::string texture = "none";  // "none", "checker", "wood"
  double texture_scale = 4;      // planes: metres per texture tile
  double plane_size = 30;        // planes: side of the drawn square (the plane's `size` key)
};

struct RenderConfig {
  CameraConfig camera;
  RenderOptionsConfig options;
  std::map<std::string, BodyLook> bodies;
  std::map<std::string, ColliderLook> colliders;
};

// Read from a body's or collider's table (type already read; a collider's own keys too, which may have set look
// keys of its kind); fill scene.render.
void readBodyLook(TableReader& r, const BodyKind& kind, const std::string& name, SceneFile& scene);
void readColliderLook(TableReader& r, const ColliderKind& kind, const std::string& name, ColliderLook look,
                      SceneFile& scene);
// The root's [camera] and [render] tables (after bodies, so `follow` can be checked against them).
void readRenderTables(TableReader& root, SceneFile& scene);

}  // namespace wobble

namespace wobble::render {
struct RenderSettings;
}

namespace wobble {

// The renderer's settings for one frame of a scene (render.* keys; the frame number seeds the noise).
render::RenderSettings renderSettings(const RenderOptionsConfig& options, int frame);

}  // namespace wobble
