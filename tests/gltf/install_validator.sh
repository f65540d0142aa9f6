#!/usr/bin/env bash
# tests/gltf/install_validator.sh PREFIX
# The test set-up of the glTF validation (ctest GltfValidator.Install, a
# fixture of GltfValidator.SuiteGlbs): `npm ci` of package.json +
# package-lock.json (this folder; the pinned gltf-validator) into PREFIX, so
# PREFIX/node_modules/gltf-validator exists. Needs the npm registry once;
# nothing is fetched again while PREFIX holds this lock's install.
# Exit 77 (ctest SKIP_RETURN_CODE) with a message when node or npm is
# missing.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
prefix=${1:?usage: install_validator.sh PREFIX}
for tool in node npm; do
  if ! command -v "$tool" >/dev/null 2>&1; then
    echo "texbake: skipped: $tool not found, so the glTF-Validator is not installed" \
      "(scripts/setup.sh installs nodejs and npm)"
    exit 77
  fi
done
mkdir -p "$prefix"
if cmp -s "$here/package-lock.json" "$prefix/package-lock.json" &&
  [ -f "$prefix/node_modules/gltf-validator/package.json" ]; then
  echo "gltf-validator already installed in $prefix"
  exit 0
fi
cp "$here/package.json" "$here/package-lock.json" "$prefix/"
(cd "$prefix" && npm ci --no-audit --no-fund --loglevel=error)
echo "installed gltf-validator $(node -p "require('$prefix/node_modules/gltf-validator/package.json').version") into $prefix"
