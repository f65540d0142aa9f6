# texbake_startup_order(TARGET LIBRARY): TARGET (an executable or module)
# names first, before everything else it needs, the libraries of LIBRARY's
# dependency closure that cost the dynamic linker the most symbol look-ups
# (cmake/startup_order.sh says why and how they are found). It changes the
# order of the search scope, not what is loaded (every one of these
# libraries is in the closure anyway). Where a symbol is defined twice, the
# first definition in the scope wins, so the order can pick another copy:
# compared binding by binding (LD_DEBUG=bindings on Debian 12) the copies
# that change are C++ inline functions, template instances and typeinfo
# (interchangeable by the one-definition rule; GCC compares typeinfo by
# name) and one C function, strlcat, which libnetcdf now takes from its own
# copy instead of libbsd's (the same BSD function).
#
# Measured on Debian 12 with its OpenImageIO 2.4 (265 libraries: 157k
# look-ups, 57k of them libopenvdb's binding to itself): `texbake --version`
# 165 -> 120 ms (hyperfine -N -w 3 -r 40, the two builds alternated); README,
# Performance. The list is worked out at configure time from the libraries
# installed, never written down: another build of OpenImageIO gets its own.
# TEXBAKE_STARTUP_ORDER=OFF leaves the link line as it is.
option(TEXBAKE_STARTUP_ORDER "Name the libraries that cost start-up the most look-ups first" ON)
set(TEXBAKE_STARTUP_ORDER_COUNT 40 CACHE STRING "How many libraries texbake_startup_order names first")

function(texbake_startup_order target library)
  # Not in sanitizer builds (their runtime must come first in the list),
  # nor when cross-compiling (ldd reads the host's libraries).
  if(NOT TEXBAKE_STARTUP_ORDER OR TEXBAKE_SANITIZE OR TEXBAKE_FUZZ OR CMAKE_CROSSCOMPILING
     OR NOT CMAKE_SYSTEM_NAME STREQUAL "Linux" OR NOT EXISTS "${library}")
    return()
  endif()
  # Worked out once per library and count; again when a listed file is gone.
  set(key "${library};${TEXBAKE_STARTUP_ORDER_COUNT}")
  set(libs "${TEXBAKE_STARTUP_ORDER_LIBS}")
  foreach(lib IN LISTS libs)
    if(NOT EXISTS "${lib}")
      set(libs "")
      break()
    endif()
  endforeach()
  if(NOT "${TEXBAKE_STARTUP_ORDER_KEY}" STREQUAL "${key}" OR libs STREQUAL "")
    execute_process(
      COMMAND sh "${CMAKE_CURRENT_FUNCTION_LIST_DIR}/startup_order.sh" "${library}"
              "${TEXBAKE_STARTUP_ORDER_COUNT}"
      OUTPUT_VARIABLE out RESULT_VARIABLE rc ERROR_QUIET)
    set(libs "")
    if(rc EQUAL 0)
      string(REPLACE "\n" ";" libs "${out}")
      list(FILTER libs INCLUDE REGEX "^/")
    endif()
    set(TEXBAKE_STARTUP_ORDER_KEY "${key}" CACHE INTERNAL "")
    set(TEXBAKE_STARTUP_ORDER_LIBS "${libs}" CACHE INTERNAL "")
    list(LENGTH libs n)
    message(STATUS "texbake: start-up order: ${n} libraries named first")
  endif()
  if(libs)
    # --no-as-needed: the executable uses none of their symbols itself, and a
    # linker defaulting to --as-needed would drop them.
    target_link_libraries(${target} PRIVATE "-Wl,--push-state,--no-as-needed" ${libs}
      "-Wl,--pop-state")
  endif()
endfunction()
