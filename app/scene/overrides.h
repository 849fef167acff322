// --set KEY=VALUE: edits the parsed scene TOML before it is read, so overridden values are checked like the file's.
#pragma once
#include <string>

#include <toml++/toml.h>

namespace wobble {

// Throws InputError when the assignment is malformed or walks through a key that is not a table.
void applyOverride(toml::table& root, const std::string& assignment);

}  // namespace wobble
