#include "app/cli/render_flags.h"

#include "app/scene/render_config.h"

namespace wobble {

void addRenderFlags(CLI::App& cmd, RenderFlags& flags) {
  cmd.add_option("--render", flags.render,
                 "Images per frame: png, exr, png,exr or none (overrides render.png / render.exr; none also turns "
                 "the video off)");
  std::string presets;
  for (const std::string& name : qualityNames()) presets += "; " + name + ": " + qualityPreset(name).summary;
  cmd.add_option("--quality", flags.quality, "Render quality preset (overrides render.quality)" + presets)
      ->check(CLI::IsMember(qualityNames()));
  cmd.add_option("--spp", flags.samples_per_pixel,
                 "Samples per pixel, the most with adaptive sampling: sets render.samples = N and "
                 "render.noise_threshold = \"auto\" (max(0.001, 1/N), Cycles' automatic threshold), so a higher N "
                 "converges further; --set render.noise_threshold=X chooses another")
      ->check(CLI::Range(1, 65536));
  cmd.add_option("--denoise", flags.denoise, "Denoise the PNG frames and video: on or off (overrides render.denoise)")
      ->check(CLI::IsMember({"on", "off"}));
  cmd.add_option("--resolution", flags.resolution, "Image size WxH, e.g. 1280x720 (overrides camera.resolution)");
  cmd.add_flag("--video", flags.video, "Encode OUT/<scene>.mp4 from the PNG frames with ffmpeg (render.video)");
}

void addSkipExistingFlag(CLI::App& cmd, bool& skip) {
  cmd.add_flag("--skip-existing", skip,
               "Do not render again a frame whose files are there from the same scene, overrides, settings, meshes "
               "and wobble build (the key in each PNG/EXR); resumes a stopped or re-queued piece");
}

}  // namespace wobble
