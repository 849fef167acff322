// Lookups in a table of kinds (body_kinds.h, collider_kinds.h): entries with a `type`, the name a scene gives.
#pragma once
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace wobble {

// The `type` values, in table order: what the reader allows.
template <typename Kind>
std::vector<std::string> kindTypes(std::span<const Kind> kinds) {
  std::vector<std::string> types;
  for (const Kind& k : kinds) types.emplace_back(k.type);
  return types;
}

// The entry of that type; throws std::out_of_range (what: "body", "collider") for a type not in the table.
template <typename Kind>
const Kind& findKind(std::span<const Kind> kinds, std::string_view type, std::string_view what) {
  for (const Kind& k : kinds)
    if (k.type == type) return k;
  throw std::out_of_range("no " + std::string(what) + " kind '" + std::string(type) + "'");
}

}  // namespace wobble
