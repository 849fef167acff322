#include "io/number_text.h"

#include <charconv>
#include <cstdio>

namespace wobble::io {

std::string formatNumber(double x, int precision) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*g", precision, x);
  return buffer;
}

std::string shortestNumber(double x) {
  char text[32];
  const auto end = std::to_chars(text, text + sizeof text, x).ptr;
  return std::string(text, end);
}

}  // namespace wobble::io
