#include "image/font_file.h"

#include <strings.h>

#include <memory>

#include <fontconfig/fontconfig.h>

namespace wobble::image {
namespace {

// fontconfig's best match for the family, when the match is that family (fontconfig otherwise offers a substitute).
std::optional<std::filesystem::path> matchFontconfig(const std::string& family) {
  FcConfig* config = FcInitLoadConfigAndFonts();  // a configuration of our own: nothing global is touched
  if (!config) return std::nullopt;
  std::unique_ptr<FcConfig, void (*)(FcConfig*)> config_owner(config, FcConfigDestroy);
  std::unique_ptr<FcPattern, void (*)(FcPattern*)> pattern(FcNameParse(
                                                               reinterpret_cast<const FcChar8*>(family.c_str())),
                                                           FcPatternDestroy);
  if (!pattern) return std::nullopt;
  FcConfigSubstitute(config, pattern.get(), FcMatchPattern);
  FcDefaultSubstitute(pattern.get());
  FcResult result = FcResultNoMatch;
  std::unique_ptr<FcPattern, void (*)(FcPattern*)> match(FcFontMatch(config, pattern.get(), &result), FcPatternDestroy);
  if (!match) return std::nullopt;
  FcChar8* file = nullptr;
  FcChar8* matched_family = nullptr;
  if (FcPatternGetString(match.get(), FC_FILE, 0, &file) != FcResultMatch ||
      FcPatternGetString(match.get(), FC_FAMILY, 0, &matched_family) != FcResultMatch)
    return std::nullopt;
  if (strcasecmp(reinterpret_cast<const char*>(matched_family), family.c_str()) != 0) return std::nullopt;
  const std::filesystem::path path(reinterpret_cast<const char*>(file));
  if (!std::filesystem::is_regular_file(path)) return std::nullopt;
  return path;
}

}  // namespace

std::optional<std::filesystem::path> findFontFile(const std::string& family, const std::filesystem::path& known_path) {
  if (auto path = matchFontconfig(family)) return path;
  if (std::filesystem::is_regular_file(known_path)) return known_path;
  return std::nullopt;
}

}  // namespace wobble::image
