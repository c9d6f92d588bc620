#!/usr/bin/env bash
# The demo on built-in data: builds the tools, writes a synthetic shelf-bin
# sequence, fuses it into a LabelOctoMap, scores every object against the
# single-view projection baselines (the paper's evaluation) and, when a display
# is available, opens the sequence in the studio.
set -euo pipefail

usage() {
  echo "usage: packaging/demo.sh [--no-gui]"
  echo "  --no-gui   do not open the studio at the end, even when DISPLAY is set"
  echo "Environment: LOM_BUILD_DIR (default build/), LOM_JOBS (default 2)"
}

open_gui=true
for arg in "$@"; do
  case "$arg" in
    --no-gui) open_gui=false ;;
    -h|--help) usage; exit 0 ;;
    *) echo "demo.sh: unknown argument '$arg'" >&2; usage >&2; exit 2 ;;
  esac
done

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${LOM_BUILD_DIR:-$root/build}"
jobs="${LOM_JOBS:-2}"
cd "$root"

step() { echo; echo "==> $*"; }

step "checking Debian packages"
packaging/install-deps.sh

step "configuring (Release) and building in build/ with -j$jobs"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j "$jobs" --target labeloctomap labeloctomap-studio

cli="$build_dir/app/labeloctomap"
studio="$build_dir/app/labeloctomap-studio"
scene="$build_dir/demo/scene"
map="$build_dir/demo/map.ot"
report="$build_dir/demo/report"

step "writing a synthetic scene"
mkdir -p "$build_dir/demo"
"$cli" synth --out "$scene" --seed 1 --objects 6

step "fusing it into a LabelOctoMap"
"$cli" fuse "$scene" --out "$map"

step "scoring each object (IU_3d against the ground-truth boxes)"
"$cli" score "$scene" --annotations "$scene/annotations.json" --map "$map" --out "$report"

echo
echo "Outputs:"
echo "  sequence:      $scene/sequence.json (frames and ground-truth annotations.json beside it)"
echo "  label map:     $map"
echo "  scores:        $report/report.md (also .json, .csv and a chart, report.svg)"
echo "  look at them:  $cli info $scene"
echo "                 $studio --map $map $scene   (the map above; without --map it fuses again)"

if $open_gui && [[ -n "${DISPLAY:-}" ]]; then
  step "opening the studio on the map (close its window to finish)"
  "$studio" --map "$map" "$scene"
elif $open_gui; then
  echo
  echo "(no DISPLAY: not opening the studio)"
fi
