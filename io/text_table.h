// TextTable: rows of strings under a header, rendered as CSV (RFC 4180 quoting: fields with a comma, quote or line
// break are quoted) or as a GitHub Markdown table. Numbers for its cells: io/number_text.h (included).
#pragma once
#include <string>
#include <vector>

#include "io/number_text.h"

namespace wobble::io {

struct TextTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  void add(std::vector<std::string> row) { rows.push_back(std::move(row)); }
  std::string csv() const;
  std::string markdown() const;
};

}  // namespace wobble::io
