// The name of one frame's file, the same for every output a frame has: "<stem>_NNNN.<extension>", the 1-based frame
// number zero-padded to four digits (more where it has more), so that a folder lists the frames in order. The stem
// is a body's name (OBJ meshes) or the scene's (PNG and EXR pictures).
#pragma once
#include <string>
#include <string_view>

namespace wobble {

std::string frameFileName(const std::string& stem, int frame, std::string_view extension);

}  // namespace wobble
