# Installs bake/texbake/texbake.h, job.h, job_options.h and every project header they include,
# transitively, under TEXBAKE_INCLUDE_DESTINATION keeping the source layout
# (texbake.h, job.h and job_options.h at the top; mapping/, mesh_io/, bake/<folder>/ below it).
# Run by `cmake --install` (CMakeLists.txt, Installation), so the set follows
# the includes as they are when installing. Inputs:
#   TEXBAKE_SOURCE_DIR           the source root
#   TEXBAKE_INCLUDE_DESTINATION  e.g. ${CMAKE_INSTALL_PREFIX}/include/texbake
# A quoted include names a header by its path from the source root
# ("mapping/proxy.h"); angle includes are the standard library's (the public
# headers include no third-party header; tests/install checks it) and are not
# followed. A quoted include that does not resolve is an error.

# The install script runs with CMake 2.x policies; include() scopes this.
cmake_policy(VERSION 3.22)

set(pending "bake/texbake/texbake.h" "bake/texbake/job.h" "bake/texbake/job_options.h")
set(headers "")
while(pending)
  list(POP_FRONT pending header)
  if(header IN_LIST headers)
    continue()
  endif()
  if(NOT EXISTS "${TEXBAKE_SOURCE_DIR}/${header}")
    message(FATAL_ERROR "texbake install: ${header} (included by a public header) not found")
  endif()
  list(APPEND headers "${header}")
  file(STRINGS "${TEXBAKE_SOURCE_DIR}/${header}" includes REGEX "^[ \t]*#[ \t]*include[ \t]*\"")
  foreach(line IN LISTS includes)
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*\"([^\"]+)\".*" "\\1" included "${line}")
    if(included MATCHES "^[^/]+$")  # a sibling of the top headers, beside them installed too
      set(included "bake/texbake/${included}")
    endif()
    list(APPEND pending "${included}")
  endforeach()
endwhile()

foreach(header IN LISTS headers)
  if(header MATCHES "^bake/texbake/(texbake|job|job_options)\\.h$")
    set(destination "${TEXBAKE_INCLUDE_DESTINATION}")
  else()
    get_filename_component(folder "${header}" DIRECTORY)
    set(destination "${TEXBAKE_INCLUDE_DESTINATION}/${folder}")
  endif()
  file(INSTALL DESTINATION "${destination}" TYPE FILE FILES "${TEXBAKE_SOURCE_DIR}/${header}")
endforeach()
