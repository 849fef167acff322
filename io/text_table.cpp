#include "io/text_table.h"

namespace wobble::io {
namespace {

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n\r") == std::string::npos) return s;
  std::string quoted = "\"";
  for (char c : s) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

std::string markdownRow(const std::vector<std::string>& cells) {
  std::string line = "|";
  for (const std::string& c : cells) {
    std::string escaped;
    for (char ch : c) escaped += ch == '|' ? std::string("\\|") : std::string(1, ch);
    line += " " + escaped + " |";
  }
  return line + "\n";
}

}  // namespace

std::string TextTable::csv() const {
  std::string text;
  const auto line = [&](const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      if (i) text += ',';
      text += csvField(cells[i]);
    }
    text += "\n";
  };
  line(header);
  for (const auto& row : rows) line(row);
  return text;
}

std::string TextTable::markdown() const {
  std::string text = markdownRow(header) + "|";
  for (std::size_t i = 0; i < header.size(); ++i) text += "---|";
  text += "\n";
  for (const auto& row : rows) text += markdownRow(row);
  return text;
}

}  // namespace wobble::io
