#!/usr/bin/env bash
# Scale of a render (issue 20, item 5): frame time against pixel count from 720p to 4K, and peak
# memory against clip length. Renders the bundled street plate scaled to each size with a preset
# (moderate) to an H.264 movie and prints, per size, seconds per frame (wall, the whole render
# over its frames, so the one-off analysis is included: use enough frames), milliseconds per
# megapixel and the peak resident set size; then the peak RSS of the same render at 720p for
# two clip lengths. CPU s/frame (user + system, ffmpeg's decoder and encoder included) is given
# too: on a machine shared with other jobs it varies less than the wall time. Usage: scripts/scale.sh [FRAMES_PER_SIZE] [SHORT_CLIP] [LONG_CLIP] [PRESET]
set -euo pipefail
cd "$(dirname "$0")/.."
frames=${1:-12}
short=${2:-24}
long=${3:-96}
preset=${4:-moderate}
pluvia=build/pluvia
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

clip() {  # clip WIDTH HEIGHT FRAMES -> path (the example looped and scaled, veryfast crf 18)
  local out="$work/plate_$1x$2_$3.mp4"
  ffmpeg -v error -y -stream_loop -1 -i examples/street/street_plate.mp4 -frames:v "$3" \
    -vf "scale=$1:$2" -c:v libx264 -preset veryfast -crf 18 "$out"
  echo "$out"
}

render() {  # render CLIP FRAMES -> "seconds peak_kib cpu_seconds"
  local log="$work/time.log"
  local start end
  start=$(date +%s.%N)
  /usr/bin/time -v -o "$log" "$pluvia" render "$1" -p "$preset" -o "$work/out.mp4" \
    --frames "0-$(($2 - 1))" >/dev/null 2>&1
  end=$(date +%s.%N)
  local user system
  user=$(awk -F': ' '/User time/ {print $2}' "$log")
  system=$(awk -F': ' '/System time/ {print $2}' "$log")
  echo "$(echo "$end - $start" | bc -l) $(awk -F': ' '/Maximum resident/ {print $2}' "$log")" \
    "$(echo "$user + $system" | bc -l)"
}

echo "scale: preset $preset, $frames frames per size, $(nproc) cores"
printf '%-10s %9s %10s %12s %12s %12s %12s\n' size Mpx s/frame ms/Mpx "CPU s/frame" "CPU ms/Mpx" \
  "peak MiB"
for size in 1280x720 1920x1080 2560x1440 3840x2160; do
  w=${size%x*} h=${size#*x}
  read -r seconds kib cpu < <(render "$(clip "$w" "$h" "$frames")" "$frames")
  mpx=$(echo "$w * $h / 1000000" | bc -l)
  printf '%-10s %9.2f %10.3f %12.1f %12.3f %12.1f %12.0f\n' "$size" "$mpx" \
    "$(echo "$seconds / $frames" | bc -l)" "$(echo "1000 * $seconds / $frames / $mpx" | bc -l)" \
    "$(echo "$cpu / $frames" | bc -l)" "$(echo "1000 * $cpu / $frames / $mpx" | bc -l)" \
    "$(echo "$kib / 1024" | bc -l)"
done

echo "memory against clip length (1280x720):"
for n in "$short" "$long"; do
  read -r seconds kib cpu < <(render "$(clip 1280 720 "$n")" "$n")
  printf '%5d frames: %7.1f s, peak %6.0f MiB\n' "$n" "$seconds" "$(echo "$kib / 1024" | bc -l)"
done
