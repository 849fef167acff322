#include "app/output/frame_name.h"

#include <cstdio>

namespace wobble {

std::string frameFileName(const std::string& stem, int frame, std::string_view extension) {
  char number[16];
  std::snprintf(number, sizeof number, "_%04d.", frame);
  return stem + number + std::string(extension);
}

}  // namespace wobble
