#!/usr/bin/env bash
# Runs Puff's libFuzzer harnesses (docs/fuzzing.md).
#
#   tests/fuzz/run.sh [--seconds N] [--seed S] [--build DIR] [--jobs J] [--replay] [HARNESS...]
#
# Builds the harnesses in DIR (default build-fuzz, configured with clang and -DPUFF_FUZZ=ON when it
# is not yet), assembles each harness's seed corpus from art/, tests/data/ and tests/fuzz/seeds/,
# replays tests/fuzz/regressions/HARNESS/ (every input that once crashed), then fuzzes each harness
# for N seconds (default 60) into DIR/corpus/HARNESS, which later runs start from. Crashes go to
# DIR/crashes/HARNESS/. Prints one line per harness (executions, coverage, corpus, crashes) and
# exits 1 if any harness crashed. --replay only replays the seeds and regressions (no fuzzing).
# --jobs J runs J harnesses at a time (default: the number of cores; each fuzzes on one core).
# --seed S makes libFuzzer's mutations repeatable (CI uses 1); by default each run draws its own.
# HARNESS: scene atlas_sidecar mesh_obj mesh_off mesh_ply mesh_stl mesh_gltf mesh_glb image_ramp
# image_gradient image_map image_detail (default: all).
set -euo pipefail
script="$(cd "$(dirname "$0")" && pwd)/$(basename "$0")"
cd "$(dirname "$script")/../.."
root=$PWD
usage_error() { echo "run.sh: $1 (see --help)" >&2; exit 2; }

seconds=60
seed=0
jobs=$(nproc)
build=build-fuzz
replay_only=0
harnesses=()
while [ $# -gt 0 ]; do
  case "$1" in
    --seconds|--seed|--build|--jobs)
      [ $# -ge 2 ] && [ -n "$2" ] || usage_error "$1 needs a value"
      case "$1" in --seconds) seconds=$2 ;; --seed) seed=$2 ;; --build) build=$2 ;; --jobs) jobs=$2 ;; esac
      shift 2 ;;
    --replay) replay_only=1; shift ;;
    -h|--help) sed -n '2,/^set -euo pipefail/{/^set /d;p}' "$script" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) usage_error "unknown option $1" ;;
    *) [[ " ${harnesses[*]-} " == *" $1 "* ]] && usage_error "harness $1 given twice"
       harnesses+=("$1"); shift ;;
  esac
done
all=(scene atlas_sidecar mesh_obj mesh_off mesh_ply mesh_stl mesh_gltf mesh_glb image_ramp image_gradient image_map image_detail)
[ ${#harnesses[@]} -gt 0 ] || harnesses=("${all[@]}")
for h in "${harnesses[@]}"; do
  [[ " ${all[*]} " == *" $h "* ]] || usage_error "no harness $h (have: ${all[*]})"
done
# Digits only and at most 9 of them, so that the shell's arithmetic never overflows.
[[ "$seconds" =~ ^[0-9]{1,9}$ ]] && [ "$seconds" -ge 1 ] || usage_error "--seconds must be a whole number in [1, 999999999]"
[[ "$seed" =~ ^[0-9]{1,9}$ ]] || usage_error "--seed must be a whole number in [0, 999999999]"
[[ "$jobs" =~ ^[0-9]{1,3}$ ]] && [ "$jobs" -ge 1 ] || usage_error "--jobs must be a whole number in [1, 999]"

command -v clang++ >/dev/null || { echo "run.sh: clang++ not found (bash setup.sh installs clang and libFuzzer)" >&2; exit 1; }
if [ ! -f "$build/CMakeCache.txt" ]; then
  CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPUFF_FUZZ=ON \
    -DPUFF_BUILD_TESTS=OFF -DPUFF_BUILD_BENCH=OFF >/dev/null
fi
cmake --build "$build" --target puff_fuzzers -j"$(nproc)" >/dev/null

# Seeds: the first byte of an image input picks its extension (fuzz_common.h): 0 .png, 1 .exr, 2 .puffimg.
image_seed() {  # image_seed FILE OUTDIR
  local b=0
  case "$1" in *.exr) b=1 ;; *.puffimg) b=2 ;; esac
  { printf "\\x0$b"; cat "$1"; } >"$2/$(basename "$1")"
}
seeds_of() {  # seeds_of HARNESS OUTDIR
  local h=$1 out=$2 f
  shopt -s nullglob
  case "$h" in
    scene) cp art/scenes/*.json tests/fuzz/seeds/scene/* "$out"/ ;;
    atlas_sidecar) cp tests/fuzz/seeds/atlas/*.json "$out"/ ;;
    mesh_*)
      local ext=${h#mesh_}
      for f in tests/data/meshes/*."$ext" art/puffs/*."$ext" tests/fuzz/seeds/mesh/*."$ext"; do cp "$f" "$out"/; done ;;
    image_ramp) for f in art/ramps/* tests/fuzz/seeds/ramp/*; do image_seed "$f" "$out"; done ;;
    image_gradient) for f in art/gradients/* tests/fuzz/seeds/gradient/*; do image_seed "$f" "$out"; done ;;
    image_detail) for f in tests/fuzz/seeds/detail/*; do image_seed "$f" "$out"; done ;;
    image_map)
      # The first byte picks one of the seed atlas's map files (in the harness's order): every
      # file with every index, so each file is seeded in its own place.
      local maps=(tests/fuzz/seeds/atlas/tiny_*.png) i
      for f in tests/fuzz/seeds/atlas/tiny_*.png tests/fuzz/seeds/atlas/tinyc_*.puffimg; do
        for i in "${!maps[@]}"; do { printf "\\x$(printf %02x "$i")"; cat "$f"; } >"$out/$i-$(basename "$f")"; done
      done ;;
  esac
  shopt -u nullglob
}

# One harness: replay, then fuzz. Writes its table row to $build/logs/HARNESS.row and what went wrong
# to $build/logs/HARNESS.err; returns 1 if it failed. Harnesses run --jobs at a time (each is one
# process on one core), their rows printed in order when all are done.
fuzz_one() {
  local h=$1
  local bin=$build/tests/fuzz/puff_fuzz_$h
  local seeds=$build/seeds/$h corpus=$build/corpus/$h crashes=$build/crashes/$h log=$build/logs/$h.log
  local row=$build/logs/$h.row err=$build/logs/$h.err
  rm -rf "$seeds"; mkdir -p "$seeds" "$corpus" "$crashes" "$(dirname "$log")"
  : >"$row"; : >"$err"
  seeds_of "$h" "$seeds"
  # Every input that ever crashed, then every seed, once each.
  local regressions=(tests/fuzz/regressions/$h/*)
  local inputs=("$seeds"/*)
  [ -e "${regressions[0]}" ] && inputs+=("${regressions[@]}")
  export UBSAN_OPTIONS=print_stacktrace=1
  # Full stacks on malloc, so that tests/lsan.supp matches the third-party leaks it names.
  export LSAN_OPTIONS="suppressions=$root/tests/lsan.supp:fast_unwind_on_malloc=0"
  if ! "$bin" -rss_limit_mb=2560 -timeout=30 "${inputs[@]}" >"$log" 2>&1; then
    { echo "$h: a seed or regression input fails; see $log"; tail -30 "$log"; } >"$err"
    printf '%-15s %8s %10s %8s %8s %7s %s\n' "$h" 0 "${#inputs[@]}" - - - "replay failed" >"$row"
    return 1
  fi
  if [ "$replay_only" = 1 ]; then
    printf '%-15s %8s %10s %8s %8s %7s %s\n' "$h" 0 "${#inputs[@]}" - - - "0 (replayed)" >"$row"
    return 0
  fi
  local status=0
  "$bin" -seed="$seed" -max_total_time="$seconds" -rss_limit_mb=2560 -malloc_limit_mb=2560 -timeout=30 -print_final_stats=1 \
    -artifact_prefix="$crashes/" "$corpus" "$seeds" >"$log" 2>&1 || status=$?
  # -a: an input that reaches the log (a detail clip's bytes) must not turn it into "binary".
  local execs last cov ft ncrash
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  last=$(grep -a -E '^#[0-9]+.*cov: ' "$log" | tail -1 || true)
  cov=$(sed -n 's/.*cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.*ft: \([0-9]*\).*/\1/p' <<<"$last")
  ncrash=$(find "$crashes" -type f | wc -l)
  printf '%-15s %8s %10s %8s %8s %7s %s\n' "$h" "$seconds" "${execs:-?}" "${cov:-?}" "${ft:-?}" \
    "$(find "$corpus" -type f | wc -l)" "$ncrash" >"$row"
  if [ "$status" != 0 ] || [ "$ncrash" != 0 ]; then
    { echo "$h: crashed (exit $status); inputs in $crashes/, log $log"
      grep -a -E 'ERROR|SUMMARY|puff fuzz' "$log" | head -5 || true; } >"$err"
    return 1
  fi
}

for h in "${harnesses[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
  fuzz_one "$h" &
done
wait
failed=0
printf '%-15s %8s %10s %8s %8s %7s %s\n' harness seconds executions cov features corpus crashes
for h in "${harnesses[@]}"; do
  cat "$build/logs/$h.row"
  if [ -s "$build/logs/$h.err" ]; then
    cat "$build/logs/$h.err" >&2
    failed=1
  fi
done
exit $failed
