// The text of app/blender/make_blend.py, compiled into the binary (blend_script.cpp is generated from it by
// app/blender/embed.cmake), so `wobble blend` works wherever the binary is.
#pragma once

namespace wobble {

extern const char* const kBlendScript;

}  // namespace wobble
