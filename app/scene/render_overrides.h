// The rendering flags shared by `wobble run`, `wobble render` and `wobble study render` (--render png,exr|none,
// --quality preview|final, --spp N, --denoise on|off, --resolution WxH, --video; app/cli/render_flags.h adds them to
// a command) as scene overrides (render.*, camera.resolution), so the scene reader checks them like the file.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace wobble {

struct RenderFlags {
  std::optional<std::string> render;   // "png", "exr", "png,exr" or "none"
  std::optional<std::string> quality;  // render.quality
  std::optional<int> spp;
  std::optional<std::string> denoise;     // "on" or "off"
  std::optional<std::string> resolution;  // "WxH"
  bool video = false;
};

// Overrides "key=value" for loadScene. Throws InputError naming the flag when a value is malformed.
std::vector<std::string> renderOverrides(const RenderFlags& flags);

}  // namespace wobble
