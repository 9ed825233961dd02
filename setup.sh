#!/usr/bin/env bash
# Installs the Debian 12 packages Puff needs to build, test and run, and only those missing.
# Idempotent and quiet when everything is already there. Run as root (or with sudo available).
set -euo pipefail

packages=(
  # toolchain
  g++ cmake make pkg-config git
  # libraries
  libglfw3-dev libglm-dev libopenmesh-dev libosmesa6-dev libegl-dev
  libopenimageio-dev nlohmann-json3-dev libcli11-dev
  # rigid bodies (scene objects with "dynamic"): the ODE physics library McGuire & Fein used
  libode-dev
  # puffview's panels: Dear ImGui (static lib with the GLFW + OpenGL 3 backends) and the stb it needs
  libimgui-dev libstb-dev
  # GL loader generator, run at configure time
  python3-glad
  # tests, a window without a display (the GLFW test), image tools (art/make-art.sh)
  libgtest-dev xvfb xauth openimageio-tools
  # formatting
  clang-format
  # the fuzz harnesses (tests/fuzz): clang with libFuzzer and its sanitizers
  clang libclang-rt-14-dev
  # charts of the speed-against-accuracy report (tests/bench/report.sh)
  gnuplot-nox
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q '^install ok installed$'; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup.sh: error: need root (or sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi
echo "setup.sh: installing ${#missing[@]} package(s): ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup.sh: done"
