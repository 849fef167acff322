// Body, collider and scene names become parts of file names (OUT/mesh/<body>_0001.obj, frames/<scene>_0001.png):
// they must be identifiers, so that no name can reach outside the output folder or make a stray file.
#pragma once
#include <string>
#include <string_view>

namespace wobble {

// "" for an identifier: 1 to kMaxNameLength (scene_limits.h) letters, digits, '_' and '-'; else what is wrong.
std::string identifierProblem(std::string_view name);

// The name in double quotes, control and non-ASCII bytes as \xNN, for messages.
std::string quotedName(std::string_view name);

}  // namespace wobble
