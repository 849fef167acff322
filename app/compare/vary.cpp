#include "app/compare/vary.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "app/scene/input_error.h"

namespace wobble {
namespace {

// Splits at commas that are outside [...], {...} and quotes.
std::vector<std::string> splitValues(const std::string& list) {
  std::vector<std::string> values(1);
  int depth = 0;
  char quote = 0;
  for (const char c : list) {
    if (quote) {
      if (c == quote) quote = 0;
    } else if (c == '"' || c == '\'') {
      quote = c;
    } else if (c == '[' || c == '{') {
      ++depth;
    } else if ((c == ']' || c == '}') && depth > 0) {
      --depth;
    } else if (c == ',' && depth == 0) {
      values.emplace_back();
      continue;
    }
    values.back() += c;
  }
  return values;
}

}  // namespace

std::string varyFlag(const VaryAxis& axis) {
  std::string text = "--vary " + axis.key + "=";
  for (std::size_t i = 0; i < axis.values.size(); ++i) text += (i ? "," : "") + axis.values[i];
  return text;
}

VaryAxis parseVary(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return InputError("--vary " + text + ": " + why +
                      "; expected KEY=V1,V2,... with KEY integrator, dt or a scene key, e.g. "
                      "--vary integrator=midpoint,rk4 or --vary jelly.ks=1e4,5e4");
  };
  const auto eq = text.find('=');
  if (eq == std::string::npos) throw bad("no '='");
  VaryAxis axis{text.substr(0, eq), {}};
  if (axis.key.empty()) throw bad("no key before '='");
  const std::string list = text.substr(eq + 1);
  if (list.empty()) throw bad("an empty list of values");
  axis.values = splitValues(list);
  for (std::size_t i = 0; i < axis.values.size(); ++i) {
    if (axis.values[i].empty()) throw bad("value " + std::to_string(i + 1) + " is empty");
    if (std::find(axis.values.begin(), axis.values.begin() + long(i), axis.values[i]) != axis.values.begin() + long(i))
      throw bad("the value " + axis.values[i] + " is given twice");
  }
  return axis;
}

VariedSetting variedSetting(const VaryAxis& axis, const std::string& value) {
  VariedSetting s;
  if (axis.key == "integrator") {
    s.integrator = value;
  } else if (axis.key == "dt") {
    char* end = nullptr;
    errno = 0;
    const double dt = std::strtod(value.c_str(), &end);
    if (end == value.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(dt))
      throw InputError(varyFlag(axis) + ": dt '" + value +
                       "' is not a number; dt takes time steps in seconds, "
                       "e.g. --vary dt=1e-3,1.2e-3");
    s.dt = dt;
  } else {
    s.set = axis.key + "=" + value;
  }
  return s;
}

}  // namespace wobble
