# The layers of ARCHITECTURE.md, checked on every ctest: a folder includes only the folders below it.
#   io/      the standard library only (of the project: nothing)
#   image/   io/ only: pictures know nothing of the renderer, the simulator or the app
#   sim/     neither render/ nor image/ nor app/ nor io/: the simulator stands alone
#   sim/solver/  the linear-solver machinery: of sim/ only sim/solver/ and sim/types.h (never the model files)
#   sim/contact/ contact, by stage: never the system, the simulation or the integrators that use it
#   sim/body.h, sim/bodies/  the model's bodies: nothing of sim/contact/
#   sim/system.*  the model: colliders and their response, never contact between bodies (sim/contact/collisions/,
#                 which Simulation joins to it)
#   render/  image/ and io/, never sim/ or app/
#   app/output/   what a run leaves on disk: app/output/, app/scene/, sim/, image/, io/ and of render/ only the camera
#                 (the picture key hashes it)
#   app/run/      the run driver, shutter and camera rig: app/run/, app/scene/, sim/, io/ and of render/ only the
#                 camera: it knows nothing of pictures or files
#   app/pictures/ never app/study/, app/commands/, app/compare/ or app/cli/
#   app/study/    never app/commands/, app/compare/ or app/cli/
#   app/compare/  never render/, app/commands/ or app/cli/ (compare_command.cpp uses it; its grid is pictures)
# Run: cmake -DROOT=<source dir> -P tests/layers.cmake (ctest runs it as the test "layers").
set(rules
  "io|render/|sim/|app/|image/"
  "image|render/|sim/|app/"
  "sim|render/|app/|io/|image/"
  "render|sim/|app/"
  "sim/contact|sim/system.h|sim/simulation.h|sim/integrators/"
  "sim/body.h|sim/contact/"
  "sim/bodies|sim/contact/"
  "sim/system.h|sim/contact/collisions/"
  "sim/system.cpp|sim/contact/collisions/"
  "app/pictures|app/study/|app/commands/|app/compare/|app/cli/"
  "app/study|app/commands/|app/compare/|app/cli/"
  "app/compare|app/commands/|app/cli/|render/")
# Folders that may include only what is listed (prefixes), besides the standard library and the packages.
set(only_rules
  "sim/solver|sim/solver/,sim/types.h"
  "app/output|app/output/,app/scene/,sim/,image/,io/,render/camera.h"
  "app/run|app/run/,app/scene/,sim/,io/,render/camera.h")
set(broken "")
foreach(rule IN LISTS rules)
  string(REPLACE "|" ";" parts "${rule}")
  list(POP_FRONT parts folder)
  if(IS_DIRECTORY "${ROOT}/${folder}")
    file(GLOB_RECURSE files "${ROOT}/${folder}/*.h" "${ROOT}/${folder}/*.cpp")
  else()
    set(files "${ROOT}/${folder}")  # one file
  endif()
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
foreach(rule IN LISTS only_rules)
  string(REPLACE "|" ";" parts "${rule}")
  list(GET parts 0 folder)
  list(GET parts 1 allowed)
  string(REPLACE "," ";" allowed "${allowed}")
  file(GLOB_RECURSE files "${ROOT}/${folder}/*.h" "${ROOT}/${folder}/*.cpp")
  foreach(file IN LISTS files)
    file(STRINGS "${file}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
    foreach(line IN LISTS includes)
      string(REGEX REPLACE "^[^\"]*\"([^\"]*)\".*$" "\\1" target "${line}")
      set(ok FALSE)
      foreach(prefix IN LISTS allowed)
        string(FIND "${target}" "${prefix}" at)
        if(at EQUAL 0)
          set(ok TRUE)
        endif()
      endforeach()
      if(NOT ok)
        file(RELATIVE_PATH from "${ROOT}" "${file}")
        string(APPEND broken "  ${from} includes ${target} (${folder}/ may include only ${allowed})\n")
      endif()
    endforeach()
  endforeach()
endforeach()
if(broken)
  message(FATAL_ERROR "layering broken (ARCHITECTURE.md):\n${broken}")
endif()
message(STATUS "layers kept: io/ includes nothing of the project, image/ only io/, sim/ nothing of render/, image/, app/ or io/, sim/solver/ nothing of the model, sim/contact/ nothing of the system, the simulation or the integrators, the bodies and the system nothing of contact between bodies, render/ nothing of sim/ or app/, app/output/ and app/run/ nothing of the app above them and of render/ only the camera, app/pictures/ and app/study/ nothing of the commands, app/compare/ nothing of render/, app/commands/ or app/cli/")
