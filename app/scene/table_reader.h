// Typed, range-checked reads from one TOML table of a scene, with errors that name the file, line, key, value and
// what is allowed. Every key a table may hold must be read (or listed with allow()); finish() then reports any
// other key as unknown, suggesting the nearest known one. A value with no place in the file came from --set or, when
// the flags (scene_flags.h) name its key, from a command-line flag: messages say which ("file (--dt): ...").
#pragma once
#include <array>
#include <filesystem>
#include <functional>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "app/scene/scene_file_use.h"
#include "app/scene/scene_flags.h"
#include "sim/types.h"

namespace wobble {

// Closed or open bounds of an allowed interval, for messages like "must be in (0, 1]".
struct Range {
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_open = false, max_open = false;

  static Range positive() { return {0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range nonNegative() { return {0}; }
  static Range unit() { return {0, 1}; }
  static Range atLeast(double m) { return {m}; }
  bool contains(double x) const;
  std::string describe() const;
};

class TableReader {
 public:
  // file: the scene file, for messages; path: the table's dotted path ("" for the root), e.g. "bodies.jelly".
  // flags: the settings laid over the scene (kept by the caller while the reader lives), for messages.
  // files: receives every file the readers of this table and its children resolve (filePath), when given.
  TableReader(const toml::table& table, std::filesystem::path file, std::string path, const SceneFlags* flags = nullptr,
              std::vector<SceneFileUse>* files = nullptr);

  double number(std::string_view key, double fallback, Range range = {});
  int integer(std::string_view key, int fallback, Range range = {});
  bool boolean(std::string_view key, bool fallback);
  std::string string(std::string_view key, std::string fallback, const std::vector<std::string>& allowed = {});
  Vec3 vec3(std::string_view key, const Vec3& fallback);
  std::array<double, 2> pair(std::string_view key, std::array<double, 2> fallback, Range range = {});
  std::optional<std::string> optionalString(std::string_view key);
  // The file a string key names (`name`, as read), relative to the scene file's folder; recorded among the files.
  std::filesystem::path filePath(std::string_view key, const std::string& name);
  // The node itself (for keys of mixed type such as a pin list); marks the key as known.
  const toml::node* node(std::string_view key);
  // A sub-table; marks the key known. Nothing when absent; an error when present but not a table.
  const toml::table* table(std::string_view key);
  // A reader of that sub-table (of an empty one when absent), of the same file and flags; marks the key known.
  TableReader child(std::string_view key);
  void allow(std::string_view key) { known_.insert(std::string(key)); }

  // Throws InputError for any key that was never read or allowed.
  void finish() const;

  // "file:line:col: key.path = value: problem" — for checks across several keys.
  [[noreturn]] void fail(std::string_view key, const std::string& problem) const;
  // "file:line:col: path.\"key\": problem" — for a problem with the key itself (a name), whose value may be a table.
  [[noreturn]] void failName(std::string_view key, const std::string& problem) const;
  std::string keyPath(std::string_view key) const;
  const std::filesystem::path& file() const { return file_; }

 private:
  const toml::node* get(std::string_view key);
  double toDouble(std::string_view key, const toml::node& node, const Range& range) const;
  std::string where(const toml::node* node, std::string_view key) const;

  const toml::table& table_;
  std::filesystem::path file_;
  std::string path_;
  std::set<std::string> known_;
  const SceneFlags* flags_;
  std::vector<SceneFileUse>* files_;
};

// `table` with the value of each of `files`' keys replaced by value(use).
toml::table withFileValues(toml::table table, const std::vector<SceneFileUse>& files,
                           const std::function<std::string(const SceneFileUse&)>& value);

// The known key nearest to an unknown one (edit distance), or "" if none is close.
std::string nearestKey(std::string_view unknown, const std::set<std::string>& known);

}  // namespace wobble
