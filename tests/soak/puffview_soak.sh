#!/usr/bin/env bash
# puffview's soak test whole: one viewer process reloads an edited scene 2,000 times (every other
# version broken) and draws 10,000 frames, its resident memory and GL objects flat
# (tests/unit/puffview_soak_test.cpp; the suite runs a sample of it). Under a private Xvfb.
#   tests/soak/puffview_soak.sh [BUILD_DIR (build)] [RELOADS (2000)] [FRAMES (10000)]
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-build}
tests=$build/tests/puff_tests_e2e
[ -x "$tests" ] || { echo "puffview_soak.sh: $tests not found: build first (cmake --build $build)" >&2; exit 2; }
reloads=${2:-2000} frames=${3:-10000}
[[ $reloads =~ ^[0-9]+$ ]] && [ "$reloads" -ge 60 ] ||
  { echo "puffview_soak.sh: RELOADS must be a whole number of at least 60 (the objects are counted after 30), got '$reloads'" >&2; exit 2; }
[[ $frames =~ ^[0-9]+$ ]] && [ "$frames" -gt 100 ] ||
  { echo "puffview_soak.sh: FRAMES must be a whole number over 100 (the baseline is taken after 100), got '$frames'" >&2; exit 2; }
PUFF_TEST_REQUIRE_GLFW=1 PUFF_SOAK_RELOADS=$reloads PUFF_SOAK_FRAMES=$frames \
  "$here/../support/with_xvfb.sh" "$tests" --gtest_filter='PuffviewSoak.*'
