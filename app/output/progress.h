// A one-line progress report (frame k of n, elapsed, remaining, and what the run wants seen meanwhile, e.g. steps it
// took again) on a terminal; silent when stderr is not one. unit names what is counted ("frame" by default; the
// studies count runs).
#pragma once
#include <chrono>
#include <string>

namespace wobble {

class Progress {
 public:
  Progress(std::string what, int total, std::string unit = "frame");  // enabled only when stderr is a terminal
  // note: appended to the line when not empty.
  void update(int done, const std::string& note = {});
  void finish();  // ends the line so later messages start on their own

 private:
  std::string what_, unit_;
  int total_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace wobble
