#!/bin/sh
# startup_order.sh LIBRARY COUNT [DIR...]: the COUNT shared libraries of
# LIBRARY's dependency closure (ldd) that ask the dynamic linker for the
# most symbol look-ups at start-up, most first, one path a line
# (cmake/StartupOrder.cmake). With DIRs, only libraries in those folders
# (the linker's default search path) are listed: one that LIBRARY finds
# through a RUNPATH of its own would not be found from an executable that
# names it.
#
# A look-up walks the process's search scope (the executable, then its
# DT_NEEDED libraries breadth-first) until it finds the symbol, so it costs
# the position of the defining library in that scope. The C++ libraries deep
# in OpenImageIO's closure bind mostly to themselves (vague linkage: vtables,
# typeinfo, template instances); on Debian 12 libopenvdb sits 33rd in
# texbake's scope, libgdal 127th, libxerces-c 199th and libgeos 256th.
# Named first by the executable, they sit at its front.
#
# The count per library: its relocations that name a symbol and are resolved
# at load time: GLOB_DAT, 64-bit absolute and TLS ones, and the JUMP_SLOTs
# of function calls too when the library is linked with BIND_NOW (otherwise
# those are resolved on first call). Libraries without a SONAME are left
# out (the executable would record their path). Prints nothing when ldd or
# readelf is missing or LIBRARY has no closure.
set -u
lib=$1
count=$2
shift 2
command -v ldd >/dev/null 2>&1 && command -v readelf >/dev/null 2>&1 || exit 0
# The allowed folders, symbolic links resolved, as " a b c ".
allowed=" "
for d in "$@"; do
  real_d=$(cd "$d" 2>/dev/null && pwd -P) && allowed="$allowed$real_d "
done
ldd "$lib" 2>/dev/null | awk '$2 == "=>" && $3 ~ /^\// {print $3}' | while read -r dep; do
  if [ $# -gt 0 ]; then
    real_dir=$(cd "$(dirname "$dep")" 2>/dev/null && pwd -P)
    case "$allowed" in *" $real_dir "*) ;; *) continue ;; esac
  fi
  dynamic=$(readelf -dW "$dep" 2>/dev/null)
  printf '%s\n' "$dynamic" | grep -q '(SONAME)' || continue
  kinds='GLOB_DAT|64|DTPMOD64|DTPOFF64|TPOFF64'
  if printf '%s\n' "$dynamic" | grep -qE '\(BIND_NOW\)|Flags:.* NOW'; then
    kinds="$kinds|JUMP_SLOT"
  fi
  n=$(readelf -rW "$dep" 2>/dev/null | grep -cE " R_[A-Z0-9_]+_($kinds) ")
  echo "$n $dep"
done | sort -rn -k1,1 | awk -v c="$count" 'NR <= c && $1 > 0 {print $2}'
