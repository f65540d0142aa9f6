#!/bin/sh
# startup_order.sh LIBRARY COUNT: the COUNT shared libraries of LIBRARY's
# dependency closure (ldd) that ask the dynamic linker for the most symbol
# look-ups at start-up, most first, one path a line (cmake/StartupOrder.cmake).
#
# A look-up walks the process's search scope (the executable, then its
# DT_NEEDED libraries breadth-first) until it finds the symbol, so it costs
# the position of the defining library in that scope. The C++ libraries deep
# in OpenImageIO's closure bind mostly to themselves (vague linkage: vtables,
# typeinfo, template instances), and on Debian they sit some 100 libraries
# down the scope. Named first by the executable, they sit at its front.
#
# The count per library: its relocations that name a symbol and are resolved
# at load time (GLOB_DAT, 64-bit absolute and TLS ones; the lazy JUMP_SLOTs
# of function calls are resolved on first call). Prints nothing when ldd or
# readelf is missing or LIBRARY has no closure.
set -u
lib=$1
count=$2
command -v ldd >/dev/null 2>&1 && command -v readelf >/dev/null 2>&1 || exit 0
ldd "$lib" 2>/dev/null | awk '$2 == "=>" && $3 ~ /^\// {print $3}' | while read -r dep; do
  n=$(readelf -rW "$dep" 2>/dev/null |
    grep -cE ' R_[A-Z0-9_]+_(GLOB_DAT|64|DTPMOD64|DTPOFF64|TPOFF64) ')
  echo "$n $dep"
done | sort -rn -k1,1 | awk -v c="$count" 'NR <= c && $1 > 0 {print $2}'
