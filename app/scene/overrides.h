// Edits of the parsed scene TOML before it is read, so overridden values are checked like the file's:
// --set KEY=VALUE (text by nature: parsed as TOML) and the flags' typed settings (scene_flags.h: no text between).
#pragma once
#include <string>

#include <toml++/toml.h>

#include "app/scene/scene_flags.h"

namespace wobble {

// Throws InputError when the assignment is malformed or walks through a key that is not a table.
void applyOverride(toml::table& root, const std::string& assignment);
// Each setting in order (a later one wins). Throws InputError when a key walks through a value (after --set).
void applyFlags(toml::table& root, const SceneFlags& flags);

}  // namespace wobble
