// Moved to scene_flags.h (the flags' typed settings); this name stays until app/study/study_render.cpp includes that.
#pragma once
#include "app/scene/scene_flags.h"
