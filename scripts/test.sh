#!/usr/bin/env bash
# Install what is missing, build Release into build/, run the whole test suite.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/setup.sh"
texbake_build
cd "$TEXBAKE_BUILD"
ctest --output-on-failure --parallel "$(nproc 2>/dev/null || echo 2)" --timeout 600
