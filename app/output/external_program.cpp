#include "app/output/external_program.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <cerrno>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "app/output/interrupt.h"

extern char** environ;

namespace fs = std::filesystem;

namespace wobble {

std::optional<fs::path> findProgram(const std::string& program) {
  const auto runnable = [](const fs::path& p) {
    std::error_code ec;
    return fs::is_regular_file(p, ec) && ::access(p.c_str(), X_OK) == 0;
  };
  if (program.empty()) return std::nullopt;
  if (program.find('/') != std::string::npos)
    return runnable(program) ? std::optional(fs::path(program)) : std::nullopt;
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && runnable(fs::path(dir) / program)) return fs::path(dir) / program;
  return std::nullopt;
}

namespace {

struct Argv {
  explicit Argv(const std::vector<std::string>& args) : copies(args) {  // posix_spawn takes char* const[]
    for (std::string& a : copies) pointers.push_back(a.data());
    pointers.push_back(nullptr);
  }
  std::vector<std::string> copies;
  std::vector<char*> pointers;
};

}  // namespace

int runProgram(const std::vector<std::string>& args, const std::optional<fs::path>& log) {
  Argv argv(args);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  if (log) {
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, log->c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  }
  pid_t pid = 0;
  const int error = posix_spawn(&pid, argv.pointers[0], &actions, nullptr, argv.pointers.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  if (error != 0) throw std::runtime_error("cannot start " + args[0] + ": " + std::generic_category().message(error));
  return waitProgram(pid, args[0]);
}

PipedProgram startPiped(const std::vector<std::string>& args) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw std::runtime_error("cannot start " + args[0] + ": " + std::generic_category().message(errno));
  Argv argv(args);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, fds[0], STDIN_FILENO);  // dup2 clears close-on-exec on stdin only
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  sigset_t defaults;  // wobble ignores SIGPIPE (it reads EPIPE instead); the child gets the usual dispositions
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGPIPE);
  posix_spawnattr_setsigdefault(&attributes, &defaults);
  posix_spawnattr_setpgroup(&attributes, 0);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  pid_t pid = 0;
  const int error = posix_spawn(&pid, argv.pointers[0], &actions, &attributes, argv.pointers.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attributes);
  ::close(fds[0]);
  if (error != 0) {
    ::close(fds[1]);
    throw std::runtime_error("cannot start " + args[0] + ": " + std::generic_category().message(error));
  }
  return {pid, fds[1]};
}

int waitProgram(int pid, const std::string& name) {
  // Polled rather than blocking: a SIGINT/SIGTERM to wobble may land on any thread, and then the program is ended.
  int status = 0;
  bool killed = false;
  for (;;) {
    const pid_t done = ::waitpid(pid, &status, WNOHANG);
    if (done == pid) break;
    if (done < 0 && errno != EINTR) throw std::runtime_error("lost track of " + name);
    if (interrupted() && !killed) killed = ::kill(pid, SIGTERM) == 0;
    ::usleep(10'000);
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace wobble
