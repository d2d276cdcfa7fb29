#!/usr/bin/env bash
# Installs the Debian packages (when missing), configures and builds pluvia into build/: every
# target, or only the ones named (`bash scripts/build.sh pluvia`: the tool without its tests).
# Idempotent: a second run only rebuilds what changed.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
if [ ! -f build/build.ninja ]; then
  cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
fi
cmake --build build -j "$(nproc)" ${1:+--target "$@"}
