// The memory budget charged while a scene is read (the limits and the estimate are in scene_limits.h): each body,
// texture and the render buffers are added to scene.estimate before they are built or loaded, and the first that
// does not fit is refused at its key, with a hint of what would fit.
#pragma once
#include <functional>
#include <string>
#include <string_view>

#include "app/scene/scene_limits.h"

namespace wobble {

class TableReader;
struct SceneFile;

// Fails at key: the scene with estimate e would be over the budget; hint ends the message ("" or "; ...").
[[noreturn]] void failOverBudget(TableReader& r, const SceneFile& scene, std::string_view key, const SceneEstimate& e,
                                 const std::string& hint);

// Adds a body to the scene's estimate before it is built, or fails at key (value as read): over the particle count
// one body may have, or over the memory budget. sizeOf(v) is the body's size with key = v; the message names the
// largest v that would fit.
void reserveBody(TableReader& r, SceneFile& scene, std::string_view key, int value,
                 const std::function<BodySize(int)>& sizeOf);

}  // namespace wobble
