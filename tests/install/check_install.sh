#!/usr/bin/env bash
# Installs the build into a temporary prefix, builds tests/install/consumer against it with
# find_package(puff), and runs it. Usage: check_install.sh BUILD_DIR SOURCE_DIR
set -euo pipefail
build=$1
src=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
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
# A game's components alone look for none of OpenMesh, GLFW, OSMesa or EGL (the first two are
# disabled outright; pkg-config modules would leave their variables in the cache).
mkdir -p "$work/components"
cat > "$work/components/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.25)
project(components LANGUAGES C CXX)
set(CMAKE_CXX_STANDARD 20)
find_package(puff REQUIRED COMPONENTS cel media sim core)
add_library(game STATIC game.cpp)
target_link_libraries(game PRIVATE puff::cel puff::media puff::sim puff::core)
CMAKE
cat > "$work/components/game.cpp" <<'CPP'
#include <puff/cel/nailboards.h>
#include <puff/media/media.h>
#include <puff/sim/simulator.h>
#ifdef __gl_h_
#error a Puff header included a GL header
#endif
int gameUsesPuff() { return puff::cel::NailboardRenderer::create() ? 1 : 0; }
CPP
cmake -S "$work/components" -B "$work/components/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_DISABLE_FIND_PACKAGE_OpenMesh=ON -DCMAKE_DISABLE_FIND_PACKAGE_glfw3=ON >"$work/components.log" 2>&1 ||
  { cat "$work/components.log" >&2; exit 1; }
cmake --build "$work/components/build" >/dev/null
if grep -E '^(OSMESA|EGL)_' "$work/components/build/CMakeCache.txt"; then
  echo "check_install: COMPONENTS cel media sim core looked for OSMesa or EGL" >&2
  exit 1
fi
# The same game without CMake, through pkg-config from the installed prefix (relocatable .pc).
pcdir=$(dirname "$(find "$work/prefix" -name puff.pc | head -1)")
printf 'int gameUsesPuff();\nint main() { return gameUsesPuff() < 0; }\n' > "$work/components/main.cpp"
# shellcheck disable=SC2046
c++ -std=c++20 "$work/components/game.cpp" "$work/components/main.cpp" -o "$work/components/pkgconfig_game" \
  $(PKG_CONFIG_PATH="$pcdir" pkg-config --cflags --libs puff)
# No installed header reaches for a GL loader or GL header: the game brings its own.
if grep -rlE '#include <(glad/|GL/|puff/glad)' "$work/prefix/include/puff"; then
  echo "check_install: an installed header includes a GL header" >&2
  exit 1
fi
# Every shader a host includes is installed.
test -f "$work/prefix/share/puff/shaders/common/frame.glsl"
pc=$(find "$work/prefix" -name puff.pc | head -1)
test -n "$pc"
test -f "$work/prefix/include/puff/core/atlas.h"
test -f "$work/prefix/lib/cmake/puff/puffConfig.cmake" || test -f "$work/prefix/lib/"*/cmake/puff/puffConfig.cmake
test -x "$work/prefix/bin/puffbake"
echo "check_install: ok"
