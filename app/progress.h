// A one-line progress report (frame k of n, elapsed, remaining) on a terminal; silent when stderr is not one.
#pragma once
#include <chrono>
#include <string>

namespace wobble {

class Progress {
 public:
  Progress(std::string what, int total);  // enabled only when stderr is a terminal
  void update(int done);
  void finish();  // ends the line so later messages start on their own

 private:
  std::string what_;
  int total_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_;
};

}  // namespace wobble
