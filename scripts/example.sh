#!/usr/bin/env bash
# The main job on the bundled example: rain over the street plate, frames written to out/street/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh pluvia  # the tool only: the test command builds the tests
./build/pluvia render examples/street/street_plate.mp4 -p examples/street/street.json \
  -o out/street/street.####.png --mkdir --stats
echo "pluvia: rained frames are in $(pwd)/out/street/ (street.0000.png ... street.0047.png)"
