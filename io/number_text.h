// Numbers as text, two ways for two readers:
//   formatNumber    printf's %.*g: `precision` significant digits ("nan", "inf" as is). Tables and messages at 3 to 6
//                   digits; at kRoundTripDigits it reads back as the same double, for files a program reads again
//                   (run.json's overrides, ffmpeg's frame rate).
//   shortestNumber  the shortest text that reads back as the same double (std::to_chars): for what a person reads or
//                   types, such as a command line (0.0012, where 17 digits print 0.0011999999999999999).
#pragma once
#include <string>

namespace wobble::io {

inline constexpr int kRoundTripDigits = 17;

std::string formatNumber(double x, int precision = 6);
std::string shortestNumber(double x);

}  // namespace wobble::io
