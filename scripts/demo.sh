#!/usr/bin/env bash
# Install what is missing, build Release into build/, then run the demo.
# Each step is one function below; later features add their own step.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
texbake_build

texbake="$TEXBAKE_BUILD/texbake"
sphere=(--proxy sphere --center 0,0,0 --radius 1 --pole 0,0,1 --equator 1,0,0)

demo_worked_example() {
  echo "== Inverse mapping: the worked example of SPEC section 2 (see README.md) =="
  echo "\$ texbake map ${sphere[*]} --dir 1,1,1 --json"
  "$texbake" map "${sphere[@]}" --dir 1,1,1 --json
  echo "   (expected u = 0.125, v = 0.695913)"
  echo
  echo "\$ texbake map ${sphere[*]} --dir 1,-1,1 --image 640x480"
  "$texbake" map "${sphere[@]}" --dir 1,-1,1 --image 640x480
  echo "   (expected u = 0.875, same v; pixel x = 559.5, y = 145.46)"
  echo
}

demo_worked_example
