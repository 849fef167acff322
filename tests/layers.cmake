# The layers of ARCHITECTURE.md, checked on every ctest: a folder includes only the folders below it.
#   io/      the standard library only (of the project: nothing)
#   sim/     neither render/ nor app/ nor io/: the simulator stands alone
#   render/  io/, never sim/ or app/
#   app/compare/  never app/commands/ or app/cli/ (compare_command.cpp uses it)
# Run: cmake -DROOT=<source dir> -P tests/layers.cmake (ctest runs it as the test "layers").
set(rules
  "io|render/|sim/|app/"
  "sim|render/|app/|io/"
  "render|sim/|app/"
  "app/compare|app/commands/|app/cli/")
set(broken "")
foreach(rule IN LISTS rules)
  string(REPLACE "|" ";" parts "${rule}")
  list(POP_FRONT parts folder)
  file(GLOB_RECURSE files "${ROOT}/${folder}/*.h" "${ROOT}/${folder}/*.cpp")
  foreach(file IN LISTS files)
    file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[^\"]*\"([^\"]*)\".*$" "\\1" target "${line}")
      # A relative include is resolved from the file's own folder.
      get_filename_component(dir "${file}" DIRECTORY)
      get_filename_component(resolved "${dir}/${target}" ABSOLUTE)
      if(NOT EXISTS "${resolved}")
        set(resolved "${ROOT}/${target}")
      endif()
      file(RELATIVE_PATH relative "${ROOT}" "${resolved}")
      foreach(forbidden IN LISTS parts)
        string(FIND "${relative}" "${forbidden}" at)
        if(at EQUAL 0)
          file(RELATIVE_PATH from "${ROOT}" "${file}")
          string(APPEND broken "  ${from} includes ${relative} (${folder}/ may not include ${forbidden})\n")
        endif()
      endforeach()
    endforeach()
  endforeach()
endforeach()
if(broken)
  message(FATAL_ERROR "layering broken (ARCHITECTURE.md):\n${broken}")
endif()
message(STATUS "layers kept: io/ includes nothing of the project, sim/ nothing of render/, app/ or io/, render/ nothing of sim/ or app/, app/compare/ nothing of app/commands/ or app/cli/")
