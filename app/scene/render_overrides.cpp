#include "app/scene/render_overrides.h"

#include <regex>
#include <sstream>

#include "app/scene/input_error.h"
#include "app/scene/render_config.h"

namespace wobble {

std::vector<std::string> renderOverrides(const RenderFlags& flags) {
  std::vector<std::string> o;
  if (flags.render) {
    bool png = false, exr = false, none = false;
    std::stringstream list(*flags.render);
    for (std::string item; std::getline(list, item, ',');) {
      if (item == "png") png = true;
      else if (item == "exr") exr = true;
      else if (item == "none") none = true;
      else throw InputError("--render " + *flags.render + ": must be png, exr, png,exr or none");
    }
    if (none && (png || exr)) throw InputError("--render " + *flags.render + ": none cannot be combined");
    if (!none && !png && !exr) throw InputError("--render " + *flags.render + ": must be png, exr, png,exr or none");
    if (none && flags.video) throw InputError("--video needs PNG frames: not with --render none");
    o.push_back(std::string("render.png=") + (png ? "true" : "false"));
    o.push_back(std::string("render.exr=") + (exr ? "true" : "false"));
    if (!png) o.push_back("render.video=false");
  }
  if (flags.quality) o.push_back("render.quality=\"" + *flags.quality + "\"");
  if (flags.spp) o.push_back("render.samples=" + std::to_string(*flags.spp));
  if (flags.denoise) o.push_back(std::string("render.denoise=") + (*flags.denoise == "on" ? "true" : "false"));
  if (flags.resolution) {
    std::smatch m;
    if (!std::regex_match(*flags.resolution, m, std::regex(R"(([0-9]{1,5})x([0-9]{1,5}))")))
      throw InputError("--resolution " + *flags.resolution + ": must be WxH, e.g. 1280x720");
    const int w = std::stoi(m[1]), h = std::stoi(m[2]);
    if (w < 2 || h < 2 || w > 16384 || h > 16384)
      throw InputError("--resolution " + *flags.resolution + ": width and height must be in [2, 16384]");
    o.push_back("camera.resolution=[" + std::to_string(w) + "," + std::to_string(h) + "]");
  }
  if (flags.video) o.push_back("render.video=true");
  return o;
}

}  // namespace wobble
