// The texts of app/blender/make_blend.py and of the module it imports, app/blender/cycles_nodes.py (shared with
// bench/cycles_scene.py), compiled into the binary (blend_script.cpp is generated from them by
// app/blender/embed.cmake), so `wobble blend` works wherever the binary is: it writes both into one folder for Blender.
#pragma once

namespace wobble {

extern const char* const kBlendScript;
extern const char* const kCyclesNodes;

}  // namespace wobble
