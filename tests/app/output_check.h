// Helpers for tests of the output contract: run the wobble binary (in the foreground or as a child to signal), and
// check an output folder against a clean run's: no temporary file, every file with a final name complete.
#pragma once
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace wobble::testing {

inline std::string slurpFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The lines of a text file that start with prefix ("v " for an OBJ's vertices), in order.
inline std::vector<std::string> linesStartingWith(const std::filesystem::path& p, const std::string& prefix) {
  std::ifstream in(p);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) lines.push_back(line);
  return lines;
}

// `[env] wobble arguments > log 2>&1`; returns the exit status (-1 when a signal ended it).
inline int runWobble(const std::string& arguments, const std::filesystem::path& log, const std::string& env = "") {
  const std::string command = env + " " + WOBBLE_BINARY + " " + arguments + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The same, as a child process the test can signal; returns its pid.
inline pid_t startWobble(const std::string& arguments, const std::filesystem::path& log, const std::string& env = "") {
  const std::string command =
      "exec env " + env + " " + WOBBLE_BINARY + " " + arguments + " > " + log.string() + " 2>&1";
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  return pid;
}

// Polls until `ready` holds or the child ends (then false). Bounded by the child: it ends by itself.
template <class Ready>
bool waitUntil(pid_t child, Ready ready) {
  for (;;) {
    if (ready()) return true;
    int status = 0;
    if (::waitpid(child, &status, WNOHANG) == child) return ready();
    ::usleep(5000);
  }
}

inline int waitExit(pid_t child) {
  int status = 0;
  ::waitpid(child, &status, 0);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Every file under out: no temporary name (hidden files other than the lock), and each file with a final name other
// than run.json has the bytes of the same file in `clean` (a complete run of the same scene). Returns the files.
inline std::vector<std::filesystem::path> expectCompleteFiles(const std::filesystem::path& out,
                                                              const std::filesystem::path& clean) {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(out)) {
    const std::string name = entry.path().filename().string();
    if (name[0] == '.') {
      EXPECT_EQ(name, ".wobble.lock") << "temporary file left: " << entry.path();
      continue;
    }
    if (!entry.is_regular_file() || name == "run.json") continue;
    const auto relative = std::filesystem::relative(entry.path(), out);
    files.push_back(relative);
    EXPECT_TRUE(slurpFile(entry.path()) == slurpFile(clean / relative)) << "differs from a clean run: " << relative;
  }
  return files;
}

}  // namespace wobble::testing
