#include "app/study/study_report.h"

#include <algorithm>
#include <fstream>
#include <thread>

#include "app/scene/input_error.h"
#include "sim/integrators/integrator.h"

namespace wobble {

std::string machineDescription() {
  std::string model = "unknown CPU";
  std::ifstream in("/proc/cpuinfo");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("model name", 0) == 0 && line.find(':') != std::string::npos) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  return model + " (" + std::to_string(std::thread::hardware_concurrency()) + " hardware threads)";
}

std::vector<std::string> selectIntegrators(const std::vector<std::string>& names,
                                           const std::vector<std::string>& skip) {
  std::vector<std::string> chosen;
  std::string allowed;
  for (std::string_view n : integratorNames()) allowed += (allowed.empty() ? "" : ", ") + std::string(n);
  if (names.empty()) {
    for (std::string_view n : integratorNames())
      if (std::find(skip.begin(), skip.end(), n) == skip.end()) chosen.emplace_back(n);
    return chosen;
  }
  for (const std::string& name : names) {
    const auto all = integratorNames();
    if (std::find(all.begin(), all.end(), name) == all.end())
      throw InputError("--integrators " + name + ": unknown integrator (allowed: " + allowed + ")");
    if (std::find(chosen.begin(), chosen.end(), name) == chosen.end()) chosen.push_back(name);
  }
  return chosen;
}

}  // namespace wobble
