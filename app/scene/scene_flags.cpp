#include "app/scene/scene_flags.h"

#include <algorithm>
#include <regex>
#include <sstream>

#include "app/scene/input_error.h"
#include "io/number_text.h"

namespace wobble {
namespace {

template <typename... F>
struct Overloaded : F... {
  using F::operator()...;
};
template <typename... F>
Overloaded(F...) -> Overloaded<F...>;

}  // namespace

std::string FlagSetting::text() const {
  return key + "=" +
         std::visit(Overloaded{[](bool b) { return std::string(b ? "true" : "false"); },
                               [](std::int64_t i) { return std::to_string(i); },
                               [](double x) { return io::formatNumber(x, io::kRoundTripDigits); },
                               [](const std::string& s) { return "\"" + s + "\""; },
                               [](const std::array<std::int64_t, 2>& a) {
                                 std::string text = "[";  // piecewise: GCC 12 warns falsely (-Wrestrict) on "[" + s
                                 text += std::to_string(a[0]);
                                 text += ',';
                                 text += std::to_string(a[1]);
                                 return text + "]";
                               }},
                    value);
}

void SceneFlags::set(std::string key, std::string flag, decltype(FlagSetting::value) value) {
  settings.push_back({std::move(key), std::move(flag), std::move(value)});
}

void SceneFlags::add(const SceneFlags& more) {
  settings.insert(settings.end(), more.settings.begin(), more.settings.end());
}

const FlagSetting* SceneFlags::find(const std::string& key) const {
  for (auto s = settings.rbegin(); s != settings.rend(); ++s)
    if (s->key == key) return &*s;
  return nullptr;
}

SceneFlags SceneFlags::yieldingTo(const std::vector<std::string>& sets) const {
  SceneFlags kept;
  for (const FlagSetting& s : settings) {
    const bool named = std::any_of(sets.begin(), sets.end(), [&](const std::string& set) {
      const std::string key = set.substr(0, set.find('='));
      return key.substr(key.find_first_not_of(' '), key.find_last_not_of(' ') - key.find_first_not_of(' ') + 1) ==
             s.key;
    });
    if (!(s.yields && named)) kept.settings.push_back(s);
  }
  return kept;
}

std::vector<std::string> SceneFlags::record() const {
  std::vector<std::string> texts;
  for (const FlagSetting& s : settings) texts.push_back(s.text());
  return texts;
}

SceneFlags renderFlagSettings(const RenderFlags& flags) {
  SceneFlags o;
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
    o.set("render.png", "--render", png);
    o.set("render.exr", "--render", exr);
    if (!png) o.set("render.video", "--render", false);
  }
  if (flags.quality) o.set("render.quality", "--quality", *flags.quality);
  if (flags.samples_per_pixel) {  // the noise threshold follows the budget (render_config.h)
    o.set("render.samples", "--spp", std::int64_t{*flags.samples_per_pixel});
    o.set("render.noise_threshold", "--spp", std::string("auto"));
    o.settings.back().yields = true;  // --set render.noise_threshold=X chooses another
  }
  if (flags.denoise) o.set("render.denoise", "--denoise", *flags.denoise == "on");
  if (flags.resolution) {
    std::smatch m;
    if (!std::regex_match(*flags.resolution, m, std::regex(R"(([0-9]{1,5})x([0-9]{1,5}))")))
      throw InputError("--resolution " + *flags.resolution + ": must be WxH, e.g. 1280x720");
    const int w = std::stoi(m[1]), h = std::stoi(m[2]);
    if (w < 2 || h < 2 || w > 16384 || h > 16384)
      throw InputError("--resolution " + *flags.resolution + ": width and height must be in [2, 16384]");
    o.set("camera.resolution", "--resolution", std::array<std::int64_t, 2>{w, h});
  }
  if (flags.video) o.set("render.video", "--video", true);
  return o;
}

}  // namespace wobble
