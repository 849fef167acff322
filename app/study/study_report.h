// Small pieces the study reports share: the machine a study ran on (CPU model, core count) for the Markdown, and
// the integrator list a --integrators option names (checked against sim's list).
#pragma once
#include <string>
#include <vector>

namespace wobble {

// "Intel(R) Xeon(R) ... (2 hardware threads)", from /proc/cpuinfo where it exists.
std::string machineDescription();

// names empty: every integrator but those in `skip`. Otherwise names as given; throws InputError naming the option
// and the allowed values for an unknown name.
std::vector<std::string> selectIntegrators(const std::vector<std::string>& names,
                                           const std::vector<std::string>& skip = {});

}  // namespace wobble
