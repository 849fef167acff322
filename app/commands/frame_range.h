// --frames A:B (or A): a 1-based inclusive frame range, as `run`, `render`, `frames`, `video` and `compare` take it.
#pragma once
#include <string>
#include <utility>

namespace wobble {

// The range of "A:B" or "A" within [1, count]; throws InputError naming what is allowed.
std::pair<int, int> parseFrameRange(const std::string& text, int count);
// The same within [first, last], which `why` explains in the message ("the run wrote frames 5:40").
std::pair<int, int> parseFrameRange(const std::string& text, int first, int last, const std::string& why);

}  // namespace wobble
