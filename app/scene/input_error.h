// The one error type of the user's input: the scene file (bad TOML, unknown keys, wrong types, values out of range,
// missing files), its --set overrides and the command-line flags. what() is the whole message for the user; the
// program exits with status 2 and writes nothing.
#pragma once
#include <stdexcept>
#include <string>

namespace wobble {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace wobble
