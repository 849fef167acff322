// `wobble compare --vary KEY=V1,V2,...`: the values a key takes, one variant each. KEY is `integrator` or `dt`
// (they become the run flags --integrator and --dt) or any scene key, as --set takes it (`jelly.ks`,
// `bodies.jelly.ks`, `slope.friction`), whose values become --set overrides: the scene reader checks them like the
// file's, so an unknown key or a value of the wrong type gets the reader's message. Values are split at commas
// outside brackets and quotes, so a TOML array is one value: `--vary camera.position=[0,5,9],[0,9,5]`.
#pragma once
#include <optional>
#include <string>
#include <vector>

namespace wobble {

struct VaryAxis {
  std::string key;
  std::vector<std::string> values;  // as typed
};

// Throws InputError naming the flag: no `=`, an empty key, an empty list or an empty value, a value repeated.
VaryAxis parseVary(const std::string& text);

// What one value sets in a run: exactly one of the three.
struct VariedSetting {
  std::optional<std::string> integrator;  // --integrator
  std::optional<double> dt;               // --dt
  std::optional<std::string> set;         // --set KEY=VALUE
};

// Throws InputError naming the flag when a dt value is not a number (the scene reader checks the rest).
VariedSetting variedSetting(const VaryAxis& axis, const std::string& value);

// "--vary KEY=V1,V2": the axis as the user typed it, for messages.
std::string varyFlag(const VaryAxis& axis);

}  // namespace wobble
