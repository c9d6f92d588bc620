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

if [[ ! -r "$list" ]]; then
  echo "install-deps: cannot read the package list $list" >&2
  exit 1
fi
wanted=()
while IFS= read -r line || [[ -n "$line" ]]; do
  line="${line%%#*}"
  line="${line//[[:space:]]/}"
  [[ -n "$line" ]] && wanted+=("$line")
done <"$list"
if ((${#wanted[@]} == 0)); then
  echo "install-deps: the package list $list names no package" >&2
  exit 1
fi

# Installed for this machine's architecture (or for all): a package installed
# only for another architecture (multiarch) does not count, and one installed
# for several is installed once here.
native="$(dpkg --print-architecture)"
missing=()
for package in "${wanted[@]}"; do
  status="$(dpkg-query -W -f='${Architecture} ${db:Status-Status}\n' "$package" 2>/dev/null |
    awk -v arch="$native" '($1 == arch || $1 == "all") && $2 == "installed" { print "installed"; exit }' ||
    true)"
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

manual() {
  echo "install-deps: $1. As root, run:" >&2
  echo "  apt-get update && apt-get install -y --no-install-recommends ${missing[*]}" >&2
  echo "then run ${BASH_SOURCE[0]} (or the command that called it) again." >&2
  exit 1
}

export DEBIAN_FRONTEND=noninteractive
say "running apt-get update"
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -q ||
  manual "apt-get update failed (or sudo refused)"
say "installing: ${missing[*]}"
"${as_root[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
  "${missing[@]}" </dev/null || manual "apt-get install failed (or sudo refused)"
say "done"
