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
# A relative LOM_BUILD_DIR is relative to where the command was started.
build_dir="$(realpath -m -- "${LOM_BUILD_DIR:-$root/build}")"
jobs="${LOM_JOBS:-2}"
cd "$root"

step() { echo; echo "==> $*"; }

step "checking Debian packages"
packaging/install-deps.sh

step "configuring (Release) and building in $build_dir with -j$jobs"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release
cmake --build "$build_dir" -j "$jobs" --target labeloctomap labeloctomap-studio

cli="$build_dir/app/labeloctomap"
studio="$build_dir/app/labeloctomap-studio"
scene="$build_dir/demo/scene"
map="$build_dir/demo/map.ot"
report="$build_dir/demo/report"

step "writing a synthetic scene"
mkdir -p "$build_dir/demo"
# Boxes edited and saved in the studio since the last demo are the user's:
# synth keeps them (it refuses the folder), and so does the demo.
synth_errors="$build_dir/demo/synth-errors.txt"
if "$cli" synth --out "$scene" --seed 1 --objects 6 2>"$synth_errors"; then
  cat "$synth_errors" >&2
elif [[ -f "$scene/sequence.json" ]] && grep -q "edited since" "$synth_errors"; then
  echo "(the scene's boxes were edited since the last demo: keeping the scene and its boxes;"
  echo " remove $scene for a fresh one)"
else
  cat "$synth_errors" >&2
  exit 1
fi

step "fusing it into a LabelOctoMap"
"$cli" fuse "$scene" --out "$map"

step "scoring each object (IU_3d against the ground-truth boxes)"
"$cli" score "$scene" --annotations "$scene/annotations.json" --map "$map" --out "$report"

echo
echo "Outputs:"
echo "  sequence:      $scene/sequence.json (frames and ground-truth annotations.json beside it)"
echo "  label map:     $map"
echo "  scores:        $report/report.md (also .json, .csv and a chart, report.svg)"
printf '  look at them:  %q info %q\n' "$cli" "$scene"
printf '                 %q --map %q %q   (the map above; without --map it fuses again)\n' \
  "$studio" "$map" "$scene"

if $open_gui && [[ -n "${DISPLAY:-}" ]]; then
  step "opening the studio on the map (close its window to finish)"
  status=0
  "$studio" --map "$map" "$scene" || status=$?
  if ((status == 3)); then
    # The studio's exit code when the display cannot be opened: the demo's
    # work is done, only the window is missing.
    echo "(DISPLAY=$DISPLAY cannot be opened: not opening the studio)"
  elif ((status != 0)); then
    exit "$status"
  fi
elif $open_gui; then
  echo
  echo "(no DISPLAY: not opening the studio)"
fi
