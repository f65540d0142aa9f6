# texbake_startup_order(TARGET LIBRARY): TARGET (an executable, module or
# shared library) names first, before everything else it needs, the
# libraries of LIBRARY's dependency closure that cost the dynamic linker the
# most symbol look-ups (cmake/startup_order.sh says why and how they are
# found), and gets the target property TEXBAKE_STARTUP_ORDER_APPLIED.
#
# It changes the order of the search scope, not what is loaded (every one
# of these libraries is in the closure anyway). Two things follow from the
# order:
# - Where a symbol is defined twice, the first definition in the scope
#   wins, so the order can pick another copy. Compared binding by binding
#   (LD_DEBUG=bindings with LD_BIND_NOW=1 on Debian 12: 168k bindings, 726
#   change owner) the copies that change are C++ inline functions, template
#   instances, vtables, typeinfo and function-local statics, interchangeable
#   by the one-definition rule (GCC compares typeinfo by name; the set of
#   symbols with more than one owner is the same 65 before and after), and
#   one C function, strlcat, which libnetcdf now takes from its own copy
#   instead of libbsd's (the same BSD function).
# - Initialisers of libraries that do not depend on each other run in
#   another order (dependencies still run first).
#
# Measured on Debian 12 with its OpenImageIO 2.4 (265 libraries: 157k
# look-ups, 57k of them libopenvdb's binding to itself): `texbake --version`
# 156 -> 117 ms (hyperfine -N -w 3 -r 40, the two builds alternated); README,
# Performance.
#
# The list is worked out at configure time from the libraries installed,
# never written down, and again whenever LIBRARY's closure (ldd) changes.
# The binary then records the sonames of those libraries, which it used to
# get through OpenImageIO only: should an update of OpenImageIO move to a
# new soname of one of them while the old one stays installed, the old
# binary would load both. Rebuild after such an update (CMake re-runs by
# itself when one of the files changes); packagers, whose builds must
# follow the distribution's transitions, should configure with
# -DTEXBAKE_STARTUP_ORDER=OFF, which leaves the link line as it is.
option(TEXBAKE_STARTUP_ORDER "Name the libraries that cost start-up the most look-ups first" ON)
set(TEXBAKE_STARTUP_ORDER_COUNT 40 CACHE STRING "How many libraries texbake_startup_order names first")

function(texbake_startup_order target library)
  # Not in sanitizer builds (their runtime must come first in the list),
  # nor when cross-compiling (ldd reads the host's libraries).
  if(NOT TEXBAKE_STARTUP_ORDER OR TEXBAKE_SANITIZE OR TEXBAKE_FUZZ OR CMAKE_CROSSCOMPILING
     OR NOT CMAKE_SYSTEM_NAME STREQUAL "Linux" OR NOT EXISTS "${library}")
    return()
  endif()
  # The key: LIBRARY's closure as ldd lists it (22 ms), the count and the
  # folders; the ranking (a few seconds) is redone only when it changes.
  execute_process(COMMAND ldd "${library}" OUTPUT_VARIABLE closure RESULT_VARIABLE rc
    ERROR_QUIET)
  if(NOT rc EQUAL 0)
    return()
  endif()
  string(REGEX REPLACE " \\(0x[0-9a-fA-F]+\\)" "" closure "${closure}")  # load addresses vary
  # The folders the linker and loader search by default: a library that
  # LIBRARY finds through a RUNPATH of its own is left out (cmake/startup_order.sh).
  set(dirs ${CMAKE_CXX_IMPLICIT_LINK_DIRECTORIES})
  string(SHA256 key "${closure};${TEXBAKE_STARTUP_ORDER_COUNT};${dirs}")
  if(NOT "${TEXBAKE_STARTUP_ORDER_KEY}" STREQUAL "${key}")
    execute_process(
      COMMAND sh "${CMAKE_CURRENT_FUNCTION_LIST_DIR}/startup_order.sh" "${library}"
              "${TEXBAKE_STARTUP_ORDER_COUNT}" ${dirs}
      OUTPUT_VARIABLE out RESULT_VARIABLE rc ERROR_QUIET)
    set(found "")
    if(rc EQUAL 0)
      string(REPLACE "\n" ";" found "${out}")
      list(FILTER found INCLUDE REGEX "^/")
    endif()
    set(TEXBAKE_STARTUP_ORDER_KEY "${key}" CACHE INTERNAL "")
    set(TEXBAKE_STARTUP_ORDER_LIBS "${found}" CACHE INTERNAL "")
    list(LENGTH found n)
    message(STATUS "texbake: start-up order: ${n} libraries named first")
  endif()
  set(libs "${TEXBAKE_STARTUP_ORDER_LIBS}")
  if(libs)
    # --no-as-needed: the target uses none of their symbols itself, and a
    # linker defaulting to --as-needed would drop them.
    target_link_libraries(${target} PRIVATE "-Wl,--push-state,--no-as-needed" ${libs}
      "-Wl,--pop-state")
    set_property(TARGET ${target} PROPERTY TEXBAKE_STARTUP_ORDER_APPLIED TRUE)
    # Configure again when one of them, or LIBRARY, is replaced.
    set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS "${library}" ${libs})
  endif()
endfunction()
