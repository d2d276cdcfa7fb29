#!/usr/bin/env bash
# Installs the Debian 12 packages pluvia needs to build, test and run.
# Idempotent: when every package is already installed it returns at once.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libopencv-dev
  libopenimageio-dev openimageio-tools
  libopencolorio-dev opencolorio-tools
  libegl-dev libgles-dev libgl-dev libepoxy-dev libegl-mesa0 libgl1-mesa-dri
  nlohmann-json3-dev libcli11-dev libeigen3-dev libtbb-dev libfmt-dev
  libgtest-dev libgmock-dev
  # The test suite's `format` check: every source as the project's .clang-format lays it out.
  clang-format
  ffmpeg
  colmap
  # For `pluvia farm slurm`'s test, which starts its own throw-away cluster (and skips where it
  # cannot, with its own munged and socket). Slurm's own services stay idle: Debian ships no
  # /etc/slurm/slurm.conf.
  slurm-wlm munge
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
