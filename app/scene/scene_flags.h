// The command-line flags that set scene keys (--integrator, --dt, --pc2 and the rendering flags --render, --quality,
// --spp, --denoise, --resolution, --video) as typed settings: each a dotted key, the flag that set it and a value.
// loadScene lays them over the scene after --set (a later one wins), as values of their own type, never as TOML text
// parsed again; the scene's readers then check them like the file's values, and a message about such a key names the
// flag ("scene.toml (--dt): simulation.dt = 1e-300: ..."). run.json records them as KEY=VALUE (record()), which
// `wobble blend` reads back like --set.
#pragma once
#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace wobble {

// The rendering flags as given on the command line (app/cli/render_flags.h adds them to `run`, `render`, `compare`).
struct RenderFlags {
  std::optional<std::string> render;  // "png", "exr", "png,exr" or "none"
  std::optional<std::string> quality;
  std::optional<int> samples_per_pixel;   // --spp
  std::optional<std::string> denoise;     // "on" or "off"
  std::optional<std::string> resolution;  // "WxH"
  bool video = false;
};

struct FlagSetting {
  std::string key;   // dotted, e.g. "render.samples"
  std::string flag;  // "--spp"
  std::variant<bool, std::int64_t, double, std::string, std::array<std::int64_t, 2>> value;
  bool yields = false;  // a value the flag brings along (--spp's threshold): a --set of the same key wins

  std::string text() const;  // "render.samples=32": TOML, read back as the same value
};

struct SceneFlags {
  std::vector<FlagSetting> settings;  // in the order they apply

  void set(std::string key, std::string flag, decltype(FlagSetting::value) value);
  void add(const SceneFlags& more);
  // The flag that set a dotted key last, or nothing.
  const FlagSetting* find(const std::string& key) const;
  std::vector<std::string> record() const;  // KEY=VALUE each, for run.json
  // Without the yielding settings whose key one of these --set KEY=VALUE texts names.
  SceneFlags yieldingTo(const std::vector<std::string>& sets) const;
};

// The rendering flags' settings: --render png,exr sets render.png and render.exr (and render.video = false without
// PNG), --quality render.quality, --spp render.samples, --denoise render.denoise, --resolution camera.resolution,
// --video render.video = true. Throws InputError naming the flag when a value is malformed.
SceneFlags renderFlagSettings(const RenderFlags& flags);

}  // namespace wobble
