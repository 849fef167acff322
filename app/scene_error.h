// The one error type of scene input: bad TOML, unknown keys, wrong types, values out of range, missing files.
// what() is the whole message for the user; the program exits with status 2 and writes nothing.
#pragma once
#include <stdexcept>
#include <string>

namespace wobble {

class SceneError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace wobble
