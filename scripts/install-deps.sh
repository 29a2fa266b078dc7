#!/usr/bin/env bash
# Installs the Debian packages Shore needs, only those missing. Usage:
#   scripts/install-deps.sh [build|bench]   (bench adds the plotting tool)
set -euo pipefail
pkgs=(g++ binutils make cmake ninja-build pkg-config libbullet-dev libeigen3-dev libgtest-dev libgmock-dev
      libbenchmark-dev libcli11-dev nlohmann-json3-dev libstb-dev)
if [[ "${1:-build}" == bench ]]; then pkgs+=(gnuplot-nox); fi

missing=()
for p in "${pkgs[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then missing+=("$p"); fi
done
[[ ${#missing[@]} -eq 0 ]] && exit 0

echo "shore: installing missing Debian packages: ${missing[*]}"
sudo=""
if [[ $(id -u) -ne 0 ]]; then
  if command -v sudo >/dev/null; then sudo=sudo; else
    echo "shore: not root and no sudo; please install: ${missing[*]}" >&2; exit 1
  fi
fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
