#!/usr/bin/env bash
# startup_order_test.sh BINARY CLOSURE_OF LIB...: BINARY's first DT_NEEDED
# entries are the sonames of LIB..., in that order (cmake/StartupOrder.cmake:
# the libraries costing start-up the most look-ups come first in the search
# scope), and every one of them is in the closure of CLOSURE_OF (the
# OpenImageIO library they were picked from), so naming them loads nothing
# that was not loaded before. Exit 1 with what differs when not.
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: startup_order_test.sh BINARY CLOSURE_OF LIB..." >&2
  exit 2
fi
binary=$1
closure_of=$2
shift 2
needed=$(readelf -dW "$binary" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
expected=()
for lib in "$@"; do
  soname=$(readelf -dW "$lib" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
  if [ -z "$soname" ]; then
    echo "startup order: $lib has no SONAME (the list should leave it out)" >&2
    exit 1
  fi
  expected+=("$soname")
done
mapfile -t first < <(printf '%s\n' "$needed" | head -n "${#expected[@]}")
if [ "${first[*]}" != "${expected[*]}" ]; then
  echo "startup order: $binary's first NEEDED entries differ" >&2
  echo "  expected: ${expected[*]}" >&2
  echo "  found:    ${first[*]}" >&2
  exit 1
fi
closure=$(ldd "$closure_of")
for name in "${expected[@]}"; do
  if ! grep -q "^[[:space:]]*$name => /" <<<"$closure"; then
    echo "startup order: $name is not in the closure of $closure_of" >&2
    exit 1
  fi
done
echo "startup order: $binary names ${#expected[@]} libraries of $(basename "$closure_of")'s closure first (${expected[0]} ... ${expected[-1]})"
