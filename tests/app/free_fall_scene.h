// The free-fall scene of the shutter and run-driver tests: a 3^3 jelly at 5 m, stepped by RK4 at 3 ms (which
// integrates free fall's quadratic exactly) and framed at 25 a second, nothing to hit; the [camera] table's shutter
// and any further camera keys given.
#pragma once
#include <string>

namespace wobble::testing {

inline std::string freeFallSceneText(double shutter, const std::string& camera = "") {
  return "[simulation]\nintegrator = \"rk4\"\ndt = 0.003\nduration = 1\nfps = 25\n\n[bodies.jelly]\ntype = "
         "\"jelly\"\nn = 3\ncenter = [0, 5, 0]\n\n[camera]\n" +
         camera + "shutter = " + std::to_string(shutter) + "\n";
}

}  // namespace wobble::testing
