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
test -f "$work/prefix/include/puff/core/atlas.h"
test -f "$work/prefix/lib/cmake/puff/puffConfig.cmake" || test -f "$work/prefix/lib/"*/cmake/puff/puffConfig.cmake
test -x "$work/prefix/bin/puffbake"
echo "check_install: ok"
