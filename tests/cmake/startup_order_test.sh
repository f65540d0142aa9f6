#!/usr/bin/env bash
# startup_order_test.sh BINARY LIB...: BINARY's first DT_NEEDED entries are
# the sonames of LIB..., in that order (cmake/StartupOrder.cmake: the
# libraries costing start-up the most look-ups come first in the search
# scope), and BINARY still needs everything it needed: every LIB is in the
# closure ldd reports for it. Exit 1 with the two lists when not.
set -euo pipefail
binary=$1
shift
needed=$(readelf -dW "$binary" | sed -n 's/.*(NEEDED).*\[\(.*\)\]/\1/p')
expected=()
for lib in "$@"; do
  soname=$(readelf -dW "$lib" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')
  expected+=("${soname:-$(basename "$lib")}")
done
mapfile -t first < <(printf '%s\n' "$needed" | head -n "${#expected[@]}")
if [ "${first[*]}" != "${expected[*]}" ]; then
  echo "startup order: $binary's first NEEDED entries differ" >&2
  echo "  expected: ${expected[*]}" >&2
  echo "  found:    ${first[*]}" >&2
  exit 1
fi
closure=$(ldd "$binary")
for name in "${expected[@]}"; do
  if ! grep -q "^[[:space:]]*$name => /" <<<"$closure"; then
    echo "startup order: $name is not resolved in $binary's closure" >&2
    exit 1
  fi
done
echo "startup order: $binary names ${#expected[@]} libraries first (${expected[0]} ... ${expected[-1]})"
