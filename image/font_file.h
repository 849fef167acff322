// Where the font of wobble's labels is: DejaVu Sans (Debian's fonts-dejavu-core, which setup.sh installs), found
// through fontconfig (libfontconfig: the file it matches for the family, if it is that family), else at the package's
// path. The same font everywhere keeps labels the same on every machine.
#pragma once
#include <filesystem>
#include <optional>
#include <string>

namespace wobble::image {

inline constexpr const char* kLabelFontFamily = "DejaVu Sans";
inline constexpr const char* kLabelFontPath = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

// The family's font file, or nothing when neither fontconfig nor `known_path` has it.
std::optional<std::filesystem::path> findFontFile(const std::string& family = kLabelFontFamily,
                                                  const std::filesystem::path& known_path = kLabelFontPath);

}  // namespace wobble::image
