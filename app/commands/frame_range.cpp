#include "app/commands/frame_range.h"

#include <sstream>

#include "app/scene/input_error.h"

namespace wobble {

std::pair<int, int> parseFrameRange(const std::string& text, int count) {
  return parseFrameRange(text, 1, count, "the scene has " + std::to_string(count) + " frames");
}

std::pair<int, int> parseFrameRange(const std::string& text, int first, int last, const std::string& why) {
  const auto bad = [&] {
    return InputError("--frames " + text + ": must be A:B or A with " + std::to_string(first) +
                      " <= A <= B <= " + std::to_string(last) + " (" + why + ")");
  };
  int a = 0, b = 0;
  std::istringstream in(text);
  char colon = 0;
  if (!(in >> a)) throw bad();
  if (in >> colon) {
    if (colon != ':' || !(in >> b)) throw bad();
  } else {
    b = a;
  }
  if (!in.eof() && in.peek() != EOF) throw bad();
  if (a < first || b < a || b > last) throw bad();
  return {a, b};
}

}  // namespace wobble
