// TextTable: rows of strings under a header, rendered as CSV (RFC 4180 quoting: fields with a comma, quote or line
// break are quoted) or as a GitHub Markdown table. formatNumber prints a double with %.*g ("nan", "inf" as is).
#pragma once
#include <string>
#include <vector>

namespace wobble::io {

struct TextTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  void add(std::vector<std::string> row) { rows.push_back(std::move(row)); }
  std::string csv() const;
  std::string markdown() const;
};

std::string formatNumber(double x, int precision = 6);

}  // namespace wobble::io
