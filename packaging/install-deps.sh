#!/usr/bin/env bash
# Installs the Debian packages listed in packaging/debian-packages.txt that are
# not installed yet. Runs apt-get as root, through sudo otherwise, never asks
# questions. `--check` only lists what is missing (exit 1 if anything is).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
list="$here/debian-packages.txt"
check_only=false

for arg in "$@"; do
  case "$arg" in
    --check) check_only=true ;;
    -h|--help)
      echo "usage: packaging/install-deps.sh [--check]"
      echo "Installs the missing packages of packaging/debian-packages.txt (Debian 12)."
      echo "  --check   only list the missing packages; exit 1 if any are missing"
      exit 0 ;;
    *) echo "install-deps: unknown argument '$arg' (try --help)" >&2; exit 2 ;;
  esac
done

say() { echo "[install-deps] $*"; }

if ! command -v dpkg-query >/dev/null || ! command -v apt-get >/dev/null; then
  echo "install-deps: dpkg/apt-get not found. This script targets Debian 12;" >&2
  echo "install the packages of $list with your system's package manager." >&2
  exit 1
fi

mapfile -t wanted < <(sed -e 's/#.*//' -e 's/[[:space:]]//g' "$list" | grep -v '^$')

missing=()
for package in "${wanted[@]}"; do
  status="$(dpkg-query -W -f='${db:Status-Status}' "$package" 2>/dev/null || true)"
  [[ "$status" == "installed" ]] || missing+=("$package")
done

if ((${#missing[@]} == 0)); then
  say "all ${#wanted[@]} required packages are installed"
  exit 0
fi

say "missing packages (${#missing[@]} of ${#wanted[@]}): ${missing[*]}"
if $check_only; then
  exit 1
fi

if [[ "$(id -u)" == 0 ]]; then
  as_root=()
elif command -v sudo >/dev/null; then
  as_root=(sudo)
  say "not root: using sudo"
else
  echo "install-deps: need root to install packages and sudo is not available." >&2
  echo "Run as root: apt-get update && apt-get install -y ${missing[*]}" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
say "running apt-get update"
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q
say "installing: ${missing[*]}"
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
  "${missing[@]}" </dev/null
say "done"
