#!/usr/bin/env bash
# Installs the build into a temporary prefix, builds tests/install/consumer against it with
# find_package(puff), and runs it; then builds and runs the example game (runtime/examples/game).
# Usage: check_install.sh BUILD_DIR SOURCE_DIR
#        check_install.sh --game PREFIX SOURCE_DIR [CMAKE_ARGS...]   the game's part alone, against
#                         an installed PREFIX (e.g. -DGAME_MEDIA_FIRE=OFF for a Puff without media
#                         in the host's frame)
set -euo pipefail
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The example game against installed PREFIX: an atlas baked and cooked by the installed puffbake
# (the game links no image library), configure, build; bad input (an uncooked atlas too) must fail
# with one line; under a private Xvfb (GLFW needs a display; tests/support/with_xvfb.sh) a 60-frame
# screenshot checked pixel by pixel (runtime/examples/game/check_screenshot.py).
check_game() {
  local prefix=$1 src=$2
  shift 2
  local game=$work/game
  mkdir -p "$game"
  "$prefix/bin/puffbake" bake -g lumpy -n 4 -s 128 -o "$game/baked" -q
  "$prefix/bin/puffbake" cook "$game/baked/puff.json" -o "$game/atlas/puff.json" -q
  cmake -S "$src/runtime/examples/game" -B "$game/build" -DCMAKE_PREFIX_PATH="$prefix" "$@" >"$game/configure.log" 2>&1 ||
    { cat "$game/configure.log" >&2; exit 1; }
  cmake --build "$game/build" -j2 >"$game/build.log" 2>&1 || { cat "$game/build.log" >&2; exit 1; }
  local exe=$game/build/puff_game fire=()
  grep -q '^GAME_MEDIA_FIRE:BOOL=ON$' "$game/build/CMakeCache.txt" && fire=(--fire)
  "$exe" --help | grep -q -- '--screenshot' || { echo "check_install: puff_game --help says nothing of --screenshot" >&2; exit 1; }
  # Bad input: one line naming the problem, a non-zero exit, before any window opens.
  local line
  for bad in "--atlas $game/none" "--atlas $game/baked" "--atlas $game/atlas --screenshot $game/no/such/dir/shot.png" "--atlas $game/atlas --frames 0"; do
    # shellcheck disable=SC2086
    if line=$("$exe" $bad 2>&1); then
      echo "check_install: puff_game $bad succeeded" >&2
      exit 1
    fi
    [ "$(printf '%s\n' "$line" | wc -l)" -eq 1 ] || { echo "check_install: puff_game $bad: not one line: $line" >&2; exit 1; }
    echo "check_install: puff_game $bad -> $line"
  done
  line=$("$exe" --atlas "$game/baked" 2>&1 || true)
  case $line in
    *"puffbake cook $game/baked/puff.json -o OUT.json"*) ;;
    *) echo "check_install: puff_game on an uncooked atlas does not say how to cook it: $line" >&2; exit 1 ;;
  esac
  if ! command -v Xvfb >/dev/null; then
    echo "check_install: Xvfb not found: the example game was built but not run"
    return 0
  fi
  "$src/tests/support/with_xvfb.sh" "$exe" --atlas "$game/atlas" --screenshot "$game/shot.png" --frames 60 \
    --width 960 --height 540
  test -s "$game/shot.png"
  python3 "$src/runtime/examples/game/check_screenshot.py" "$game/shot.png" "${fire[@]}"
}

if [ "${1:-}" = "--game" ]; then
  [ $# -ge 3 ] || { echo "usage: check_install.sh --game PREFIX SOURCE_DIR [CMAKE_ARGS...]" >&2; exit 2; }
  prefix=$(cd "$2" && pwd)
  src=$3
  shift 3
  check_game "$prefix" "$src" "$@"
  echo "check_install: game ok"
  exit 0
fi

build=$1
src=$2
cmake --install "$build" --prefix "$work/prefix" >/dev/null
cmake -S "$src/tests/install/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/consumer" -j2 >/dev/null
"$work/consumer/consumer" "$work/atlas"
"$work/consumer/host_loader" "$work/atlas2"
# Puff's loader is private: no glad symbol of its own name in any installed library.
if nm -A --defined-only "$work/prefix/lib/"*puff* "$work/prefix/lib/"*/*puff* 2>/dev/null | grep -E ' (glad_|gladLoad|GLAD_GL_)'; then
  echo "check_install: an installed library defines glad's own symbols" >&2
  exit 1
fi
# A game's components alone look for none of OpenMesh, GLFW, OSMesa, EGL or OpenImageIO (the first
# two are disabled outright; pkg-config modules would leave their variables in the cache), and such
# a game, linked without any image library, loads a cooked atlas.
"$work/prefix/bin/puffbake" cook "$work/atlas/puff.json" -o "$work/cooked/puff.json" -q
mkdir -p "$work/components"
cat > "$work/components/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.25)
project(components LANGUAGES C CXX)
set(CMAKE_CXX_STANDARD 20)
find_package(puff REQUIRED COMPONENTS cel media sim core)
add_executable(game game.cpp main.cpp)
target_link_libraries(game PRIVATE puff::cel puff::media puff::sim puff::core)
CMAKE
cat > "$work/components/game.cpp" <<'CPP'
#include <cstdio>
#include <puff/cel/nailboards.h>
#include <puff/core/atlas.h>
#include <puff/media/media.h>
#include <puff/sim/simulator.h>
#ifdef __gl_h_
#error a Puff header included a GL header
#endif
int gameUsesPuff(const char* sidecar) {
  if (sidecar == nullptr) return puff::cel::NailboardRenderer::create() ? 0 : 1;  // linked, not run: no GL here
  auto atlas = puff::core::loadAtlas(sidecar);
  if (!atlas) {
    std::fprintf(stderr, "game: %s\n", atlas.error().message.c_str());
    return 1;
  }
  std::printf("game: %s: %dx%d, %zu maps\n", sidecar, atlas->desc.width, atlas->desc.height, atlas->maps.size());
  return atlas->maps.size() == 3 ? 0 : 1;
}
CPP
printf 'int gameUsesPuff(const char*);\nint main(int, char** argv) { return gameUsesPuff(argv[1]); }\n' > "$work/components/main.cpp"
cmake -S "$work/components" -B "$work/components/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenMesh=ON -DCMAKE_DISABLE_FIND_PACKAGE_glfw3=ON >"$work/components.log" 2>&1 ||
  { cat "$work/components.log" >&2; exit 1; }
cmake --build "$work/components/build" >/dev/null
if grep -E '^(OSMESA|EGL|OIIO)_' "$work/components/build/CMakeCache.txt"; then
  echo "check_install: COMPONENTS cel media sim core looked for OSMesa, EGL or OpenImageIO" >&2
  exit 1
fi
"$work/components/build/game" "$work/cooked/puff.json"
# The uncooked atlas, in the same program: one error that says how to cook it.
if "$work/components/build/game" "$work/atlas/puff.json" 2>"$work/uncooked.log"; then
  echo "check_install: a game with no image library loaded PNG maps" >&2
  exit 1
fi
grep -q 'puffbake cook' "$work/uncooked.log" || { cat "$work/uncooked.log" >&2; exit 1; }
# The same game without CMake, through pkg-config from the installed prefix (relocatable .pc).
pcdir=$(dirname "$(find "$work/prefix" -name puff.pc | head -1)")
# shellcheck disable=SC2046
c++ -std=c++20 "$work/components/game.cpp" "$work/components/main.cpp" -o "$work/components/pkgconfig_game" \
  $(PKG_CONFIG_PATH="$pcdir" pkg-config --cflags --libs puff)
"$work/components/pkgconfig_game" "$work/cooked/puff.json"
# No installed header reaches for a GL loader or GL header: the game brings its own.
if grep -rlE '#include <(glad/|GL/|puff/glad)' "$work/prefix/include/puff"; then
  echo "check_install: an installed header includes a GL header" >&2
  exit 1
fi
# The helpers the libraries and tools share (puff_support) stay in the build tree.
if [ -e "$work/prefix/include/puff/support" ] || grep -rl 'puff/support/' "$work/prefix/include/puff"; then
  echo "check_install: puff_support's headers are installed or included by an installed header" >&2
  exit 1
fi
test -f "$work/prefix/include/puff/platform/gl_context.h"
# Every shader a host includes is installed.
test -f "$work/prefix/share/puff/shaders/common/frame.glsl"
pc=$(find "$work/prefix" -name puff.pc | head -1)
test -n "$pc"
test -f "$work/prefix/include/puff/core/atlas.h"
test -f "$work/prefix/lib/cmake/puff/puffConfig.cmake" || test -f "$work/prefix/lib/"*/cmake/puff/puffConfig.cmake
test -x "$work/prefix/bin/puffbake"
check_game "$work/prefix" "$src"
echo "check_install: ok"
