// Runs gnuplot, an optional external program, on a script file: `PROGRAM -e "out='TEMP'" SCRIPT`, where the script
// writes its picture to the file named by the variable out. The picture is produced under a temporary name and
// renamed to `output` only when gnuplot succeeds, so a failed plot leaves no broken PNG. Never throws: a missing
// program or a failed run comes back as a one-line message (gnuplot's own messages go to SCRIPT.log).
// Parameters: script, output (the PNG to produce), program (a name looked up on PATH or a path; "gnuplot").
#pragma once
#include <filesystem>
#include <optional>
#include <string>

namespace wobble {

struct PlotResult {
  bool ok = false;
  std::string message;  // what was written, or why nothing was
};

PlotResult runGnuplot(const std::filesystem::path& script, const std::filesystem::path& output,
                      const std::string& program = "gnuplot");

// A gnuplot single-quoted string literal.
std::string gnuplotQuote(const std::string& text);

}  // namespace wobble
