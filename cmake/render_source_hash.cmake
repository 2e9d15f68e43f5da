# Writes OUT: a header defining LIGHTBENCH_RENDER_SOURCE_HASH, the SHA-256 of
# every file in core/ and integrators/ (sorted, with their relative paths).
# A cached reference is keyed by it: a change to the rendering code makes new
# references, a commit that touches only docs or experiments does not.
file(GLOB_RECURSE files RELATIVE "${SRC}" "${SRC}/core/*" "${SRC}/integrators/*")
list(SORT files)
set(all "")
foreach(f IN LISTS files)
  file(SHA256 "${SRC}/${f}" h)
  string(APPEND all "${f} ${h}\n")
endforeach()
string(SHA256 total "${all}")
string(SUBSTRING "${total}" 0 16 short)
set(text "#pragma once\n#define LIGHTBENCH_RENDER_SOURCE_HASH \"${short}\"\n")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT "${old}" STREQUAL "${text}")
  file(WRITE "${OUT}" "${text}")
endif()
