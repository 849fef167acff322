#include "gnuplot.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <sstream>
#include <system_error>
#include <vector>

extern char** environ;

namespace fs = std::filesystem;

namespace wobble {

std::optional<fs::path> findProgram(const std::string& program) {
  const auto runnable = [](const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
  };
  if (program.empty()) return std::nullopt;
  if (program.find('/') != std::string::npos) return runnable(program) ? std::optional(fs::path(program)) : std::nullopt;
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && runnable(fs::path(dir) / program)) return fs::path(dir) / program;
  return std::nullopt;
}

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
                       "--gnuplot); the CSV and Markdown are written. Plot later with: gnuplot " + script.string()};
  std::string temp_name = ".";  // appended piecewise: GCC 12 warns falsely (-Wrestrict) on "." + std::string
  temp_name += output.filename().string();
  temp_name += ".tmp" + std::to_string(::getpid());
  const fs::path temp = output.parent_path() / temp_name;
  const fs::path log = script.string() + ".log";
  const std::string set_out = "out=" + gnuplotQuote(temp.string());
  std::vector<std::string> args = {found->string(), "-e", set_out, script.string()};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  pid_t pid = 0;
  const int spawn_error = posix_spawn(&pid, found->c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  std::error_code ignored;
  if (spawn_error != 0) {
    return {false, "no plot " + output.filename().string() + ": cannot start " + found->string() + ": " +
                       std::generic_category().message(spawn_error)};
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) return {false, "no plot " + output.filename().string() + ": lost track of gnuplot"};
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || !fs::is_regular_file(temp, ignored)) {
    fs::remove(temp, ignored);
    return {false, "no plot " + output.filename().string() + ": gnuplot failed (see " + log.string() + ")"};
  }
  fs::rename(temp, output, ignored);
  if (ignored) return {false, "no plot " + output.filename().string() + ": " + ignored.message()};
  fs::remove(log, ignored);  // nothing to keep when it worked
  return {true, "wrote " + output.string()};
}

}  // namespace wobble
