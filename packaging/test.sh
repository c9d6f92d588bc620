#!/usr/bin/env bash
# Installs missing packages, builds everything (Release) in build/ and runs
# every test with ctest. GUI tests need an X server because Debian's VTK
# renders through X: without DISPLAY the whole ctest run goes under xvfb-run.
# Exits non-zero when the build or any test fails.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
# A relative LOM_BUILD_DIR is relative to where the command was started.
build_dir="$(realpath -m -- "${LOM_BUILD_DIR:-$root/build}")"
jobs="${LOM_JOBS:-2}"
cd "$root"

step() { echo; echo "==> $*"; }

step "checking Debian packages"
packaging/install-deps.sh

step "configuring (Release) in $build_dir"
cmake -S "$root" -B "$build_dir" -DCMAKE_BUILD_TYPE=Release

step "building with -j$jobs"
cmake --build "$build_dir" -j "$jobs"

step "running the tests"
ctest_command=(ctest --test-dir "$build_dir" --output-on-failure)
if [[ -z "${DISPLAY:-}" ]]; then
  echo "(no DISPLAY: running the tests under xvfb-run)"
  ctest_command=(xvfb-run -a -s "-screen 0 1280x1024x24" "${ctest_command[@]}")
fi
log="$build_dir/ctest-output.log"
set +e
"${ctest_command[@]}" </dev/null 2>&1 | tee "$log"
status=${PIPESTATUS[0]}
set -e

echo
summary="$(grep -E '^[0-9]+% tests passed' "$log" | tail -n 1 || true)"
if [[ -z "$summary" ]]; then
  echo "test.sh: ctest printed no summary (exit code $status)" >&2
  exit $((status == 0 ? 1 : status))
fi
echo "ctest: $summary"
exit "$status"
