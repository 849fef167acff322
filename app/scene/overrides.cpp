#include "app/scene/overrides.h"

#include <algorithm>
#include <sstream>
#include <type_traits>
#include <variant>
#include <vector>

#include "app/scene/input_error.h"

namespace wobble {
namespace {

std::vector<std::string> split(const std::string& dotted) {
  std::vector<std::string> parts;
  std::stringstream in(dotted);
  for (std::string part; std::getline(in, part, '.');) parts.push_back(part);
  return parts;
}

// A bare word is not TOML; take it as the string the user meant (--set simulation.integrator=midpoint).
toml::node_view<toml::node> parseValue(toml::table& holder, const std::string& text) {
  try {
    holder = toml::parse("value = " + text);
  } catch (const toml::parse_error&) {
    holder = toml::table{{"value", text}};
  }
  return holder["value"];
}

// The table that holds the last component of `path`, created as needed; `what` names the edit in messages.
toml::table& parentTable(toml::table& root, const std::vector<std::string>& path, const std::string& what) {
  toml::table* table = &root;
  for (std::size_t i = 0; i + 1 < path.size(); ++i) {
    toml::node* next = table->get(path[i]);
    if (!next) next = &table->insert(path[i], toml::table{}).first->second;
    if (!next->is_table()) throw InputError(what + ": '" + path[i] + "' is a value, not a table of keys");
    table = next->as_table();
  }
  return *table;
}

}  // namespace

void applyOverride(toml::table& root, const std::string& assignment) {
  const auto eq = assignment.find('=');
  const std::string key = eq == std::string::npos ? "" : assignment.substr(0, eq);
  std::vector<std::string> path = split(key);
  if (eq == std::string::npos || path.empty() ||
      std::any_of(path.begin(), path.end(), [](auto& p) { return p.empty(); }))
    throw InputError("--set " + assignment + ": expected KEY=VALUE with a dotted key, e.g. --set bodies.jelly.ks=2800");

  // Shorthand: a body or collider name standing first.
  if (path.size() > 1 && !root.contains(path[0]))
    for (const char* group : {"bodies", "colliders"})
      if (const auto* t = root[group].as_table(); t && t->contains(path[0])) {
        path.insert(path.begin(), group);
        break;
      }

  toml::table holder;
  auto value = parseValue(holder, assignment.substr(eq + 1));
  toml::table& table = parentTable(root, path, "--set " + assignment);
  value.node()->visit([&](auto& concrete) { table.insert_or_assign(path.back(), concrete); });
}

void applyFlags(toml::table& root, const SceneFlags& flags) {
  for (const FlagSetting& s : flags.settings) {
    const std::vector<std::string> path = split(s.key);
    toml::table& table = parentTable(root, path, s.flag + " (" + s.text() + ")");
    std::visit(
        [&](const auto& value) {
          if constexpr (std::is_same_v<std::decay_t<decltype(value)>, std::array<std::int64_t, 2>>)
            table.insert_or_assign(path.back(), toml::array{value[0], value[1]});
          else table.insert_or_assign(path.back(), value);
        },
        s.value);
  }
}

}  // namespace wobble
