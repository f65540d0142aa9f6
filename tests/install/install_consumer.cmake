# ctest InstallConsumer (issue #10): texbake installs as a CMake package that
# another project finds and links. Run with `cmake -P` from
# tests/CMakeLists.txt, with
#   SOURCE_DIR  texbake's source root      BUILD_DIR  its build folder
#   WORK_DIR    a scratch folder (emptied) CONFIG     the build type
#   VERSION     the project's version      CXX_COMPILER, CXX_LAUNCHER (may be empty)
# Steps, each fatal on failure:
#   1. bring texbake and texbake_shared up to date and `cmake --install` the
#      build into WORK_DIR/prefix;
#   2. check the installed tree: the package files, libtexbake.so, no static
#      module library, and headers that include only standard headers
#      (<name> without '.' or '/') and each other;
#   3. configure and build examples/consumer against the prefix alone
#      (CMAKE_PREFIX_PATH) in a folder of its own and run it on data/: it
#      writes bunny.ply and bunny.obj + .mtl + .png, which must be non-empty,
#      and bunny_job.ply through run_job (<texbake/job.h>), which it checks
#      equals bunny.ply;
#   4. run the installed `texbake --version`, and `texbake bake` on the same
#      two jobs: its outputs must equal the consumer's byte for byte.
cmake_minimum_required(VERSION 3.22)

set(prefix "${WORK_DIR}/prefix")
set(consumer_build "${WORK_DIR}/consumer-build")
set(out "${WORK_DIR}/out")
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE status)
  if(NOT status EQUAL 0)
    string(REPLACE ";" " " command "${ARGN}")
    message(FATAL_ERROR "failed (${status}): ${command}")
  endif()
endfunction()

# 1. Install.
run("${CMAKE_COMMAND}" --build "${BUILD_DIR}" --config "${CONFIG}" --target texbake texbake_shared)
run("${CMAKE_COMMAND}" --install "${BUILD_DIR}" --config "${CONFIG}" --prefix "${prefix}")

# 2. The installed tree.
foreach(file bin/texbake lib/libtexbake.so include/texbake/texbake.h
    lib/cmake/texbake/texbakeConfig.cmake lib/cmake/texbake/texbakeConfigVersion.cmake
    lib/cmake/texbake/texbakeTargets.cmake)
  if(NOT EXISTS "${prefix}/${file}")
    message(FATAL_ERROR "not installed: ${prefix}/${file}")
  endif()
endforeach()
file(GLOB_RECURSE archives "${prefix}/*.a")
if(archives)
  message(FATAL_ERROR "static libraries installed (libtexbake.so holds the modules): ${archives}")
endif()
file(GLOB_RECURSE headers RELATIVE "${prefix}/include/texbake" "${prefix}/include/texbake/*")
foreach(header IN LISTS headers)
  file(STRINGS "${prefix}/include/texbake/${header}" includes REGEX "^[ \t]*#[ \t]*include")
  foreach(line IN LISTS includes)
    if(line MATCHES "^[ \t]*#[ \t]*include[ \t]*<([^>]*)>")
      if(CMAKE_MATCH_1 MATCHES "[./]")
        message(FATAL_ERROR "installed ${header} includes a third-party header: ${line}")
      endif()
    elseif(line MATCHES "^[ \t]*#[ \t]*include[ \t]*\"([^\"]*)\"")
      if(NOT EXISTS "${prefix}/include/texbake/${CMAKE_MATCH_1}")
        message(FATAL_ERROR "installed ${header} includes ${CMAKE_MATCH_1}, not installed")
      endif()
    else()
      message(FATAL_ERROR "installed ${header}: unexpected include: ${line}")
    endif()
  endforeach()
endforeach()

# 3. The consumer, against the prefix only.
set(configure "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/examples/consumer" -B "${consumer_build}"
  "-DCMAKE_PREFIX_PATH=${prefix}" "-DCMAKE_BUILD_TYPE=${CONFIG}"
  "-DCMAKE_CXX_COMPILER=${CXX_COMPILER}")
if(CXX_LAUNCHER)
  list(APPEND configure "-DCMAKE_CXX_COMPILER_LAUNCHER=${CXX_LAUNCHER}")
endif()
run(${configure})
run("${CMAKE_COMMAND}" --build "${consumer_build}" --config "${CONFIG}")
find_program(consumer texbake_consumer PATHS "${consumer_build}" "${consumer_build}/${CONFIG}"
  NO_DEFAULT_PATH REQUIRED)
run("${consumer}" "${SOURCE_DIR}/data" "${out}")
foreach(file bunny.ply bunny.obj bunny.mtl bunny.png bunny_job.ply)
  file(SIZE "${out}/${file}" size)  # fatal when missing
  if(size EQUAL 0)
    message(FATAL_ERROR "${out}/${file} is empty")
  endif()
endforeach()

# 4. The installed command line: --version, and the same two jobs give the
# same bytes (libtexbake.so and the statically linked executable agree).
execute_process(COMMAND "${prefix}/bin/texbake" --version RESULT_VARIABLE status
  OUTPUT_VARIABLE version_line OUTPUT_STRIP_TRAILING_WHITESPACE)
if(NOT status EQUAL 0 OR NOT version_line STREQUAL "texbake ${VERSION}")
  message(FATAL_ERROR "${prefix}/bin/texbake --version: exit ${status}, \"${version_line}\"")
endif()
set(cli_out "${WORK_DIR}/cli")
file(MAKE_DIRECTORY "${cli_out}")
set(job bake "${SOURCE_DIR}/data/bunny00.off" --texture "${SOURCE_DIR}/data/earth.jpg"
  --proxy sphere --up y -q)
run("${prefix}/bin/texbake" ${job} -o "${cli_out}/bunny.ply")
run("${prefix}/bin/texbake" ${job} --uv generate --size 512 -o "${cli_out}/bunny.obj")
foreach(file bunny.ply bunny.obj bunny.mtl bunny.png)
  execute_process(COMMAND "${CMAKE_COMMAND}" -E compare_files "${out}/${file}" "${cli_out}/${file}"
    RESULT_VARIABLE differ)
  if(differ)
    message(FATAL_ERROR "the consumer's ${file} differs from texbake bake's (${cli_out})")
  endif()
endforeach()
message(STATUS "InstallConsumer: installed into ${prefix}, consumer ran, ${version_line}")
