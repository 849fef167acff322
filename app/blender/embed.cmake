# Generates OUTPUT, a C++ file defining wobble::kBlendScript as the text of INPUT (app/commands/blend_script.h).
file(READ ${INPUT} text)
file(WRITE ${OUTPUT} "// Generated from ${INPUT} by app/blender/embed.cmake: do not edit.\n"
  "#include \"app/commands/blend_script.h\"\n\nnamespace wobble {\n\n"
  "const char* const kBlendScript = R\"wobble_py(${text})wobble_py\";\n\n}  // namespace wobble\n")
