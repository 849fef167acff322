#include "app/scene/toml_depth.h"

#include <string>

namespace wobble {
namespace {

// Skips a string starting at text[i] (a quote), multi-line forms included; returns the index after it and counts
// the newlines it spans. An unterminated string runs to the end (the parser reports it).
std::size_t skipString(std::string_view text, std::size_t i, int& line) {
  const char quote = text[i];
  const bool multi = text.substr(i, 3) == std::string(3, quote);
  const std::string_view end = multi ? std::string_view(quote == '"' ? "\"\"\"" : "'''") : text.substr(i, 1);
  for (i += end.size(); i < text.size(); ++i) {
    if (text[i] == '\n') {
      if (!multi) return i;  // a newline ends a one-line string (as an error, for the parser)
      ++line;
    } else if (text[i] == '\\' && quote == '"') {
      if (i + 1 < text.size() && text[i + 1] == '\n') ++line;
      ++i;
    } else if (text.substr(i, end.size()) == end) {
      return i + end.size();
    }
  }
  return text.size();
}

}  // namespace

std::optional<NestingExcess> findExcessNesting(std::string_view text, int max_depth) {
  std::string open;  // the open '[' and '{', innermost last
  int line = 1, dots = 0;
  bool key = true;  // in a key (a header, or before '=') rather than a value: only there are dots nesting
  for (std::size_t i = 0; i < text.size();) {
    const char c = text[i];
    const int start_line = line;
    if (c == '"' || c == '\'') {
      i = skipString(text, i, line);
      if (line != start_line) dots = 0;
      continue;
    }
    if (c == '#') {
      while (i < text.size() && text[i] != '\n') ++i;
      continue;
    }
    if (c == '\n') {
      ++line, dots = 0;
      key = open.empty();  // inside a multi-line array the next line holds values
    } else if (c == '[' || c == '{') {
      open += c;
      key = c == '{' || (key && open.size() <= 2);  // a header [a] or [[a]] holds a key; an array holds values
    } else if (c == ']' || c == '}') {
      if (!open.empty()) open.pop_back();
    } else if (c == '=') {
      key = false;
    } else if (c == ',') {
      key = !open.empty() && open.back() == '{';
    } else if (c == '.' && key) {
      ++dots;
    }
    if (int(open.size()) + dots > max_depth) return NestingExcess{line, int(open.size()) + dots};
    ++i;
  }
  return std::nullopt;
}

}  // namespace wobble
