#include "app/scene/identifier.h"

#include <algorithm>
#include <cstdio>

#include "app/scene/scene_limits.h"

namespace wobble {
namespace {

bool identifierChar(char c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == '-';
}

}  // namespace

std::string identifierProblem(std::string_view name) {
  const std::string rule =
      "a name must be 1 to " + std::to_string(kMaxNameLength) + " letters, digits, '_' or '-' (it names output files)";
  if (name.empty()) return "empty; " + rule;
  if (name.size() > kMaxNameLength) return std::to_string(name.size()) + " characters long; " + rule;
  if (!std::all_of(name.begin(), name.end(), identifierChar)) return "not an identifier; " + rule;
  return "";
}

std::string quotedName(std::string_view name) {
  std::string out = "\"";
  for (const char c : name) {
    if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\') {
      out += c;
    } else {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", static_cast<unsigned char>(c));
      out += hex;
    }
  }
  return out + "\"";
}

}  // namespace wobble
