#include "app/study/gnuplot.h"

#include <stdexcept>
#include <system_error>

#include "app/output/external_program.h"
#include "io/atomic_file.h"

namespace fs = std::filesystem;

namespace wobble {

std::string gnuplotQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("''") : std::string(1, c);
  return quoted + "'";
}

PlotResult runGnuplot(const fs::path& script, const fs::path& output, const std::string& program) {
  const auto found = findProgram(program);
  if (!found)
    return {false, "no plot " + output.filename().string() + ": the program '" + program +
                       "' was not found (install gnuplot, e.g. apt-get install gnuplot-nox, or name it with "
                       "--gnuplot); the CSV and Markdown are written. Plot later with: gnuplot " +
                       script.string()};
  const fs::path temp = io::temporarySibling(output);
  const fs::path log = script.string() + ".log";
  const std::string set_out = "out=" + gnuplotQuote(temp.string());
  int status = 0;
  try {
    status = runProgram({found->string(), "-e", set_out, script.string()}, log);
  } catch (const std::runtime_error& e) {
    return {false, "no plot " + output.filename().string() + ": " + e.what()};
  }
  std::error_code ignored;
  if (status != 0 || !fs::is_regular_file(temp, ignored)) {
    fs::remove(temp, ignored);
    return {false, "no plot " + output.filename().string() + ": gnuplot failed (see " + log.string() + ")"};
  }
  fs::rename(temp, output, ignored);
  if (ignored) return {false, "no plot " + output.filename().string() + ": " + ignored.message()};
  fs::remove(log, ignored);  // nothing to keep when it worked
  return {true, "wrote " + output.string()};
}

}  // namespace wobble
