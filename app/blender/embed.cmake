# Generates OUTPUT, a C++ file defining wobble::kBlendScript and wobble::kCyclesNodes as the texts of SCRIPT
# (make_blend.py) and MODULE (cycles_nodes.py, which the script imports) (app/commands/blend_script.h).
file(READ ${SCRIPT} script)
file(READ ${MODULE} module)
file(WRITE ${OUTPUT} "// Generated from ${SCRIPT} and ${MODULE} by app/blender/embed.cmake: do not edit.\n"
  "#include \"app/commands/blend_script.h\"\n\nnamespace wobble {\n\n"
  "const char* const kBlendScript = R\"wobble_py(${script})wobble_py\";\n\n"
  "const char* const kCyclesNodes = R\"wobble_py(${module})wobble_py\";\n\n}  // namespace wobble\n")
