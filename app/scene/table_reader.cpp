#include "app/scene/table_reader.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "app/scene/identifier.h"
#include "app/scene/input_error.h"
#include "io/number_text.h"

namespace wobble {
namespace {

// What the user wrote, for messages; strings quoted as in TOML.
std::string show(const toml::node& node) {
  std::ostringstream out;
  node.visit([&](const auto& value) {
    if constexpr (toml::is_string<decltype(value)>) out << '"' << value.get() << '"';
    else out << value;
  });
  return out.str();
}

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] != b[j - 1])});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

bool Range::contains(double x) const {
  if (std::isnan(x)) return false;
  return (min_open ? x > min : x >= min) && (max_open ? x < max : x <= max);
}

std::string Range::describe() const {
  if (std::isinf(max)) return std::string(min_open ? "> " : ">= ") + io::formatNumber(min);
  if (std::isinf(min)) return std::string(max_open ? "< " : "<= ") + io::formatNumber(max);
  return std::string("in ") + (min_open ? "(" : "[") + io::formatNumber(min) + ", " + io::formatNumber(max) +
         (max_open ? ")" : "]");
}

std::string nearestKey(std::string_view unknown, const std::set<std::string>& known) {
  std::string best;
  std::size_t best_distance = std::max<std::size_t>(2, unknown.size() / 3) + 1;
  for (const std::string& k : known) {
    const std::size_t d = editDistance(unknown, k);
    if (d < best_distance) best_distance = d, best = k;
  }
  return best;
}

TableReader::TableReader(const toml::table& table, std::filesystem::path file, std::string path,
                         const SceneFlags* flags, std::vector<SceneFileUse>* files)
    : table_(table), file_(std::move(file)), path_(std::move(path)), flags_(flags), files_(files) {}

std::filesystem::path TableReader::filePath(std::string_view key, const std::string& name) {
  std::filesystem::path path = file_.parent_path() / name;
  if (files_) files_->push_back({keyPath(key), path});
  return path;
}

std::string TableReader::keyPath(std::string_view key) const {
  return path_.empty() ? std::string(key) : path_ + "." + std::string(key);
}

std::string TableReader::where(const toml::node* node, std::string_view key) const {
  std::string w = file_.string();
  const auto& src = (node ? node : &static_cast<const toml::node&>(table_))->source();
  if (src.begin.line > 0) {
    w += ':';  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on ":" + std::string
    w += std::to_string(src.begin.line);
    w += ':';
    w += std::to_string(src.begin.column);
  } else if (node) {  // from the command line: no position in the file
    const FlagSetting* flag = flags_ ? flags_->find(keyPath(key)) : nullptr;
    w += " (" + (flag ? flag->flag : std::string("--set")) + ")";
  }
  return w;
}

void TableReader::fail(std::string_view key, const std::string& problem) const {
  const toml::node* node = table_.get(key);
  std::string message = where(node, key) + ": " + keyPath(key);
  if (node) message += " = " + show(*node);
  throw InputError(message + ": " + problem);
}

void TableReader::failName(std::string_view key, const std::string& problem) const {
  const toml::node* node = table_.get(key);
  const std::string path = path_.empty() ? quotedName(key) : path_ + "." + quotedName(key);
  throw InputError(where(node, key) + ": " + path + ": " + problem);
}

const toml::node* TableReader::get(std::string_view key) {
  known_.insert(std::string(key));
  return table_.get(key);
}

const toml::node* TableReader::node(std::string_view key) { return get(key); }

// Every number of a float key passes here: inf and nan are refused whatever the range (TOML allows them, no key
// means them), and so are integers a double cannot hold exactly (toml++ gives no value for those).
double TableReader::toDouble(std::string_view key, const toml::node& node, const Range& range) const {
  constexpr std::int64_t kExact = std::int64_t{1} << 53;
  if (!node.is_number()) fail(key, "must be a number (" + range.describe() + ")");
  if (const auto* i = node.as_integer(); i && (i->get() > kExact || i->get() < -kExact))
    fail(key, "an integer beyond 2^53 is not exactly a float; write it as a float, e.g. 1e16");
  const double value = node.value<double>().value();
  const bool bounded = std::isfinite(range.min) || std::isfinite(range.max);
  if (!std::isfinite(value)) fail(key, "must be a finite number" + (bounded ? " (" + range.describe() + ")" : ""));
  return value;
}

double TableReader::number(std::string_view key, double fallback, Range range) {
  const toml::node* node = get(key);
  const double value = node ? toDouble(key, *node, range) : fallback;
  if (!range.contains(value)) fail(key, "must be " + range.describe());
  return value;
}

int TableReader::integer(std::string_view key, int fallback, Range range) {
  const toml::node* node = get(key);
  std::int64_t value = fallback;
  if (node) {
    if (!node->is_integer()) fail(key, "must be a whole number (" + range.describe() + ")");
    value = node->as_integer()->get();
  }
  if (!range.contains(double(value))) fail(key, "must be " + range.describe());
  if (value > std::numeric_limits<int>::max() || value < std::numeric_limits<int>::min())
    fail(key, "must be a 32-bit whole number (" + range.describe() + ")");
  return static_cast<int>(value);
}

bool TableReader::boolean(std::string_view key, bool fallback) {
  const toml::node* node = get(key);
  if (!node) return fallback;
  if (!node->is_boolean()) fail(key, "must be true or false");
  return node->as_boolean()->get();
}

std::string TableReader::string(std::string_view key, std::string fallback, const std::vector<std::string>& allowed) {
  const toml::node* node = get(key);
  std::string value = std::move(fallback);
  if (node) {
    if (!node->is_string()) fail(key, "must be a string");
    value = node->as_string()->get();
  }
  if (!allowed.empty() && std::find(allowed.begin(), allowed.end(), value) == allowed.end()) {
    std::string list;
    for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
    fail(key, "must be one of: " + list);
  }
  return value;
}

std::optional<std::string> TableReader::optionalString(std::string_view key) {
  if (!table_.get(key)) {
    allow(key);
    return std::nullopt;
  }
  return string(key, "");
}

Vec3 TableReader::vec3(std::string_view key, const Vec3& fallback) {
  const toml::node* node = get(key);
  if (!node) return fallback;
  const toml::array* array = node->as_array();
  const auto numeric = [](const toml::node& n) { return n.is_number(); };
  if (!array || array->size() != 3 || !std::all_of(array->begin(), array->end(), numeric))
    fail(key, "must be an array of three numbers, e.g. [0, 1, 0]");
  Vec3 v;
  for (int i = 0; i < 3; ++i) v[i] = toDouble(key, (*array)[i], {});
  return v;
}

std::array<double, 2> TableReader::pair(std::string_view key, std::array<double, 2> fallback, Range range) {
  const toml::node* node = get(key);
  if (node) {
    const toml::array* array = node->as_array();
    if (!array || array->size() != 2 || !(*array)[0].is_number() || !(*array)[1].is_number())
      fail(key, "must be an array of two numbers (" + range.describe() + ")");
    fallback = {toDouble(key, (*array)[0], range), toDouble(key, (*array)[1], range)};
  }
  if (!range.contains(fallback[0]) || !range.contains(fallback[1])) fail(key, "both must be " + range.describe());
  return fallback;
}

const toml::table* TableReader::table(std::string_view key) {
  const toml::node* node = get(key);
  if (node && !node->is_table()) fail(key, "must be a table");
  return node ? node->as_table() : nullptr;
}

TableReader TableReader::child(std::string_view key) {
  static const toml::table kEmpty;
  const toml::table* sub = table(key);
  return TableReader(sub ? *sub : kEmpty, file_, keyPath(key), flags_, files_);
}

void TableReader::finish() const {
  for (const auto& [key, node] : table_) {
    const std::string name(key.str());
    if (known_.count(name)) continue;
    std::string message = where(&node, name) + ": unknown key '" + keyPath(name) + "'";
    if (const std::string near = nearestKey(name, known_); !near.empty())
      message += "; did you mean '" + keyPath(near) + "'?";
    std::string list;
    for (const auto& k : known_) list += (list.empty() ? "" : ", ") + k;
    throw InputError(message + " (allowed here: " + list + ")");
  }
}

toml::table withFileValues(toml::table table, const std::vector<SceneFileUse>& files,
                           const std::function<std::string(const SceneFileUse&)>& value) {
  for (const SceneFileUse& use : files)
    if (auto* text = table.at_path(use.key).as_string()) *text = value(use);
  return table;
}

}  // namespace wobble
