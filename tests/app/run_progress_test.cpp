// `wobble run`'s progress line on a terminal says when the run takes steps again (docs/energy.md, "A step that gains
// is taken again"), and stays quiet off one. The run writes to a pseudo-terminal (openpty) standing in for stderr.
// Oracle: run.json's energy.retakes, the simulation's own count, against what the line says.
#include <fcntl.h>
#include <pty.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "app/commands/run_command.h"
#include "tests/app/scratch_dir.h"
#include "tests/app/simulate_only.h"

namespace wobble {
namespace {

class RunProgress : public testing::ScratchDir {
 protected:
  // jelly_trampoline under backward Euler at 1/60 s, its jelly thrown down at `speed` m/s, three frames at 60 fps.
  RunOptions thrown(double speed) const {
    RunOptions o = testing::simulateOnly("jelly_trampoline", dir() / "out", "backward-euler", 1.0 / 60);
    o.sets = {"jelly.velocity=[0,-" + std::to_string(speed) + ",0]", "simulation.fps=60"};
    o.frames = "1:3";
    o.progress = true;
    return o;
  }
  // What the run writes to stderr when stderr is a terminal (or, terminal = false, a file).
  static std::string stderrOf(const RunOptions& o, bool terminal) {
    int master = -1, slave = -1;
    std::FILE* file = nullptr;
    if (terminal) {
      if (openpty(&master, &slave, nullptr, nullptr, nullptr) != 0) return "<no pseudo-terminal>";
    } else {
      file = std::tmpfile();
      slave = fileno(file);
    }
    std::fflush(stderr);
    const int saved = dup(STDERR_FILENO);
    dup2(slave, STDERR_FILENO);
    runScene(o);
    std::fflush(stderr);
    dup2(saved, STDERR_FILENO);
    close(saved);
    std::string text;
    char buffer[4096];
    if (terminal) {
      close(slave);
      fcntl(master, F_SETFL, O_NONBLOCK);
      for (ssize_t n; (n = read(master, buffer, sizeof buffer)) > 0;) text.append(buffer, std::size_t(n));
      close(master);
    } else {
      std::rewind(file);
      for (std::size_t n; (n = std::fread(buffer, 1, sizeof buffer, file)) > 0;) text.append(buffer, n);
      std::fclose(file);
    }
    return text;
  }
  long retakes() const {
    std::ifstream in(dir() / "out" / "run.json");
    return nlohmann::json::parse(in)["energy"]["retakes"].get<long>();
  }
};

// At 150 m/s the cloth's first step of the impact gains energy and is taken again in halves (docs/energy.md).
TEST_F(RunProgress, ARunThatRetakesAStepSaysSoOnTheTerminal) {
  const std::string text = stderrOf(thrown(150), true);
  ASSERT_EQ(retakes(), 1);
  EXPECT_NE(text.find("frame 3 of 3"), std::string::npos) << text;
  EXPECT_NE(text.find("1 step retaken in halves (energy)"), std::string::npos) << text;
}

TEST_F(RunProgress, ARunWithoutRetakesSaysNothingOfThem) {
  const std::string text = stderrOf(thrown(15), true);
  ASSERT_EQ(retakes(), 0);
  EXPECT_NE(text.find("frame 3 of 3"), std::string::npos) << text;
  EXPECT_EQ(text.find("retaken"), std::string::npos) << text;
}

TEST_F(RunProgress, OffATerminalTheLineStaysQuiet) {
  const std::string text = stderrOf(thrown(150), false);
  ASSERT_EQ(retakes(), 1);
  EXPECT_EQ(text.find("frame"), std::string::npos) << text;
  EXPECT_EQ(text.find("retaken"), std::string::npos) << text;
}

}  // namespace
}  // namespace wobble
