// Helpers shared by the renderer tests: a scratch directory removed at the end of the test, and small scenes.
#pragma once
#include "render/scene.h"
#include "tests/temp_dir.h"

namespace wobble::render::test {

using wobble::test::TempDir;

}  // namespace wobble::render::test
