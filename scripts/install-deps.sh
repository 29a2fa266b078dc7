#!/usr/bin/env bash
# Installs the Debian packages Shore needs, only those missing. Usage:
#   scripts/install-deps.sh [build|bench|viewer|fuzz|memcheck]...   (bench adds the plotting
#   tool; viewer the OpenGL renderer's and shore-viewer's: GLFW, Dear ImGui, libepoxy, Mesa's
#   EGL and llvmpipe, Xvfb for the window test; fuzz clang with libFuzzer and
#   llvm-symbolizer; memcheck Valgrind)
set -euo pipefail
pkgs=(g++ binutils make cmake ninja-build pkg-config libbullet-dev libeigen3-dev libgtest-dev libgmock-dev
      libbenchmark-dev libcli11-dev nlohmann-json3-dev libstb-dev libzstd-dev)
fuzz_pkgs=(clang libclang-rt-dev llvm)
viewer_pkgs=(libglfw3-dev libimgui-dev libepoxy-dev libegl-dev libgl-dev libegl-mesa0 libgl1-mesa-dri xvfb xauth)
for group in "${@:-build}"; do
  case "$group" in
    build) ;;
    bench) pkgs+=(gnuplot-nox) ;;
    viewer) pkgs+=("${viewer_pkgs[@]}") ;;
    fuzz) pkgs+=("${fuzz_pkgs[@]}") ;;
    memcheck) pkgs+=(valgrind) ;;
    *) echo "install-deps.sh: unknown group $group (build, bench, viewer, fuzz, memcheck)" >&2; exit 2 ;;
  esac
done

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
