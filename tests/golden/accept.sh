#!/usr/bin/env bash
# Accepts new golden references: copies every CASE.actual.png from the golden output directory to
# tests/golden/references/CASE.png.
#   tests/golden/accept.sh [BUILD_DIR (build)]
# The tests write to BUILD_DIR/tests/golden-out (or to $PUFF_GOLDEN_OUTPUT_DIR when it is set).
# Look at the actual and diff images first: this makes them the new truth.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../../build}
out=${PUFF_GOLDEN_OUTPUT_DIR:-$build/tests/golden-out}
refs=$here/references
shopt -s nullglob
files=("$out"/*.actual.png)
if [ ${#files[@]} -eq 0 ]; then
  echo "accept.sh: no *.actual.png in $out: nothing to accept" >&2
  exit 1
fi
mkdir -p "$refs"
for f in "${files[@]}"; do
  name=$(basename "$f" .actual.png)
  cp "$f" "$refs/$name.png"
  echo "accept.sh: accepted $name"
done
