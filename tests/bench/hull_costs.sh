#!/usr/bin/env bash
# Where the tumbling hull's time goes: dust-roll's frames drawn by the hull and by the blend
# (puff_gpubench --groups tumble) with the shaders as they are, then with one phase of the hull's march
# left out at a time (a copy of shaders/ with one line changed, read through --shader-dir). What a
# variant saves is what that phase costs; its pictures are wrong, so only its time is kept.
#   bash tests/bench/hull_costs.sh [BUILD (build)] [--csv FILE] [puff_gpubench options, e.g. --reps 3]
# (BUILD and FILE relative to where it is run; the options are puff_gpubench's timing ones: it sets
# --groups, --samples 1 and --shader-dir itself.)
# Variants:
#   as-is               the shaders as they are
#   no-screen-distance  a ray that misses takes the field's estimate of its distance, not the one
#                       measured on the screen near the ink's outer edge (screenDistance's bisection)
#   no-depth-probe      a hit is not followed half a pixel into the hull (hullDepth: the antialiased inner edge)
# Writes CSV (variant, then puff_gpubench's columns) to --csv FILE or stdout. Not a test.
set -euo pipefail
case ${1:-} in -h | --help) sed -n '2,14p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;; esac
build=build
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then build=$(realpath -m "$1"); shift; fi
csv=
args=()
while [ $# -gt 0 ]; do
  case $1 in
    --csv) csv=$(realpath -m "${2:?--csv needs a file}"); shift 2 ;;
    --groups | --shader-dir | --scenes) echo "hull_costs.sh: error: $1 is this script's to set" >&2; exit 2 ;;
    *) args+=("$1"); shift ;;
  esac
done
cd "$(dirname "$0")/../.."
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
bash tests/bench/gpu.sh pack "$build" "$tmp/package" >/dev/null

# variant NAME OLD NEW: shaders/ copied to $tmp/NAME with the one line OLD of cel/hull_march.glsl
# made NEW (an error unless OLD is there exactly once).
variant() {
  cp -r shaders "$tmp/$1"
  python3 - "$tmp/$1/cel/hull_march.glsl" "$2" "$3" <<'PY'
import sys
path, old, new = sys.argv[1:4]
text = open(path).read()
if text.count(old) != 1:
    sys.exit(f"hull_costs.sh: {path}: expected one '{old}', found {text.count(old)}")
open(path, "w").write(text.replace(old, new))
PY
}
cp -r shaders "$tmp/as-is"
variant no-screen-distance "if (ink > 0.0 && h.nearest <= reach + pixel)" "if (false)"
variant no-depth-probe "if (wantEdge) h.deepest" "if (false) h.deepest"

out=$tmp/out.csv
for v in as-is no-screen-distance no-depth-probe; do
  echo "hull_costs.sh: $v" >&2
  bash "$tmp/package/gpu.sh" run --groups tumble --samples 1 --shader-dir "$tmp/$v" "${args[@]}" \
    --csv "$tmp/$v.csv" 2> >(grep -v '^puff_gpubench: ' >&2)
  if [ ! -s "$out" ]; then sed -n '1s/^/variant,/p' "$tmp/$v.csv" > "$out"; fi
  tail -n +2 "$tmp/$v.csv" | sed "s/^/$v,/" >> "$out"
done
if [ -n "$csv" ]; then cp "$out" "$csv"; else cat "$out"; fi
