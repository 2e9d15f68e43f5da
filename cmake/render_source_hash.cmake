cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
# Writes OUT: a header defining
#  * LIGHTBENCH_RENDER_SOURCE_HASH, the SHA-256 of every file in core/ and
#    integrators/, and experiments/chunks.* (sorted, with their relative
#    paths): it keys what depends on all the rendering code (a distributed
#    render's chunks, a run's identity);
#  * LIGHTBENCH_INTEGRATOR_SOURCE_HASHES, per folder of integrators/, the
#    SHA-256 of the files that integrator compiles from: all of core/, the
#    shared files at the top of integrators/ (the render loop, the path-length
#    and emission helpers; not registry*, which names every integrator),
#    experiments/chunks.* (how a reference's seeded chunks are rendered and
#    averaged), its own folder, every folder it reaches by
#    #include "integrators/…", transitively (a shared module such as
#    integrators/bidirectional/ counts whole, its .cpp files too), and its own
#    entry of the registry table: the lines from `{"NAME",` to the next entry
#    (how its settings are read and which configurations are unbiased).
#    A cached reference is keyed by its integrator's hash
#    (experiments/reference.cpp): a change to that code makes new references;
#    adding or fixing another integrator does not (issue 39), nor does a
#    commit that touches only docs or the rest of experiments/. An integrator
#    registered under a name that is not its folder's gets no entry here and is
#    keyed by LIGHTBENCH_RENDER_SOURCE_HASH, all of the code: never stale.
file(GLOB_RECURSE files RELATIVE "${SRC}" "${SRC}/core/*" "${SRC}/integrators/*" "${SRC}/experiments/chunks.*")
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
  if(f MATCHES "^(core/|experiments/chunks\\.)")
    list(APPEND shared ${f})
  elseif(f MATCHES "^integrators/[^/]+$")
    if(NOT f MATCHES "^integrators/registry[._]")
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

# Each registry entry's lines, in entry_NAME: an entry starts with `{"NAME",`
# at the table's indentation and runs to the next one or to the table's end.
set(current "")
if(EXISTS "${SRC}/integrators/registry.cpp")
  file(STRINGS "${SRC}/integrators/registry.cpp" registry_lines ENCODING UTF-8)
endif()
foreach(line IN LISTS registry_lines)
  if(line MATCHES "^      {\"([a-z_0-9]+)\",")
    set(current ${CMAKE_MATCH_1})
  elseif(line MATCHES "^  }")  # the table's "  };"
    set(current "")
  endif()
  if(current)
    string(APPEND entry_${current} "${line}\n")
  endif()
endforeach()

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
  string(REGEX REPLACE "^integrators/" "" name ${dir})
  string(APPEND text "registry entry:\n${entry_${name}}")
  string(SHA256 h "${text}")
  string(SUBSTRING "${h}" 0 16 h)
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
