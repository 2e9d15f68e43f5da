cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
# Writes OUT: a header defining
#  * LIGHTBENCH_RENDER_SOURCE_HASH, the SHA-256 of every file in core/ and
#    integrators/ (sorted, with their relative paths): it keys what depends on
#    all the rendering code (a distributed render's chunks, a run's identity);
#  * LIGHTBENCH_INTEGRATOR_SOURCE_HASHES, per folder of integrators/, the
#    SHA-256 of the files that integrator compiles from: all of core/, the
#    shared files at the top of integrators/ (the render loop, the path-length
#    and emission helpers; not registry.*, which names every integrator), its
#    own folder, and every folder it reaches by #include "integrators/…",
#    transitively (a shared module such as integrators/bidirectional/ counts
#    whole, its .cpp files too). A cached reference is keyed by its
#    integrator's hash (experiments/reference.cpp): a change to that code
#    makes new references; adding or fixing another integrator does not
#    (issue 39), nor does a commit that touches only docs or experiments.
file(GLOB_RECURSE files RELATIVE "${SRC}" "${SRC}/core/*" "${SRC}/integrators/*")
list(SORT files)
set(all "")
foreach(f IN LISTS files)
  file(SHA256 "${SRC}/${f}" h)
  set(sha_${f} ${h})
  string(APPEND all "${f} ${h}\n")
endforeach()
string(SHA256 total "${all}")
string(SUBSTRING "${total}" 0 16 short)

set(shared "")  # core/ and the top of integrators/
set(folders "")
foreach(f IN LISTS files)
  if(f MATCHES "^core/")
    list(APPEND shared ${f})
  elseif(f MATCHES "^integrators/[^/]+$")
    if(NOT f MATCHES "^integrators/registry\\.")
      list(APPEND shared ${f})
    endif()
  elseif(f MATCHES "^(integrators/[^/]+)/")
    list(APPEND folders ${CMAKE_MATCH_1})
  endif()
endforeach()
list(REMOVE_DUPLICATES folders)

# The files of folder `dir` (recursively), in `out`.
function(folder_files dir out)
  set(r "")
  foreach(f IN LISTS files)
    if(f MATCHES "^${dir}/")
      list(APPEND r ${f})
    endif()
  endforeach()
  set(${out} ${r} PARENT_SCOPE)
endfunction()

set(table "")
foreach(dir IN LISTS folders)
  set(reached ${dir})
  folder_files(${dir} queue)
  list(APPEND queue ${shared})
  set(seen "")
  while(queue)
    list(POP_FRONT queue f)
    if(f IN_LIST seen)
      continue()
    endif()
    list(APPEND seen ${f})
    file(STRINGS "${SRC}/${f}" includes REGEX "^#include \"integrators/[^/\"]+/")
    foreach(line IN LISTS includes)
      if(line MATCHES "^#include \"(integrators/[^/\"]+)/" AND NOT CMAKE_MATCH_1 IN_LIST reached)
        list(APPEND reached ${CMAKE_MATCH_1})
        folder_files(${CMAKE_MATCH_1} more)
        list(APPEND queue ${more})
      endif()
    endforeach()
  endwhile()
  set(used ${shared})
  foreach(d IN LISTS reached)
    folder_files(${d} more)
    list(APPEND used ${more})
  endforeach()
  list(SORT used)
  set(text "")
  foreach(f IN LISTS used)
    string(APPEND text "${f} ${sha_${f}}\n")
  endforeach()
  string(SHA256 h "${text}")
  string(SUBSTRING "${h}" 0 16 h)
  string(REGEX REPLACE "^integrators/" "" name ${dir})
  if(VERBOSE)
    message("${name}: ${reached}")
  endif()
  string(APPEND table "  {\"${name}\", \"${h}\"},\n")
endforeach()

string(CONCAT text "#pragma once\n#define LIGHTBENCH_RENDER_SOURCE_HASH \"${short}\"\n"
       "#define LIGHTBENCH_INTEGRATOR_SOURCE_HASHES { \\\n${table}}\n")
string(REPLACE "},\n" "}, \\\n" text "${text}")
if(EXISTS "${OUT}")
  file(READ "${OUT}" old)
endif()
if(NOT "${old}" STREQUAL "${text}")
  file(WRITE "${OUT}" "${text}")
endif()
