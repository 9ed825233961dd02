#!/usr/bin/env bash
# Regenerates docs/report/ (speed against accuracy) and the figure tables the docs quote
# (one source for every figure): runs the benchmarks, keeps their CSVs, draws the charts with
# gnuplot (SVG), writes the markdown tables from the CSVs and the page docs/report/README.md.
#   tests/bench/report.sh [BUILD_DIR (build)] [--only all|cel|media|paper|coverage|shadows|tumble|tables (all)] [puffbench options]
#     all     puffbench (cel, then media), puff_bench_media and puff_bench_coverage: every CSV in docs/report/
#     cel     puffbench --part cel only: cel.csv; the other CSVs are kept
#     media   puffbench --part media only: media.csv and stability.csv; the other CSVs are kept
#     paper   puff_bench_media only: paper.csv; the other CSVs are kept
#     coverage puff_bench_coverage only: coverage.csv (the media passes over what the media cover,
#             against over the whole frame and against no media); the other CSVs are kept
#     shadows puffbench --part shadows only: shadows.csv (both shadow methods against the exact ones);
#             the other CSVs are kept (--only all does not run it: about 20 minutes on llvmpipe)
#     tumble  puffbench --part tumble only: tumble.csv (multi-view atlases turned through yaw, pitch and
#             roll against the cel reference); the other CSVs are kept (--only all does not run it)
#     gpu     the GPU benchmark's package (tests/bench/gpu.sh) run on this machine's llvmpipe:
#             gpu/llvmpipe.csv; gpu.md and gpu-s1.svg, gpu-s4.svg chart it beside every GPU's CSV in
#             docs/report/gpu/ (docs/bench/gpu.md; --only all does not run it)
#     tables  runs nothing: the charts and tables again from the CSVs there are
#   puffbench options, e.g. --reps 5 --size 640 480 --physical (docs/bench/README.md lists them).
# Every table is generated from one CSV and says which, with the command, date and machine that
# produced it (docs/report/runs.tsv keeps them): docs/report/media-budget.md (what --max-error
# measures: the scenes' own methods), docs/report/paper-tables.md (Table 1 and Fig. 12 from paper.csv),
# docs/bench/media-tables.md (the same from docs/bench/media-llvmpipe-2core.csv), docs/report/coverage.md
# (from coverage.csv).
# Needs a build with PUFF_BUILD_BENCH=ON (the default) and gnuplot (Debian: gnuplot-nox).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=build
if [ $# -gt 0 ] && [ "${1#-}" = "$1" ]; then build=$1; shift; fi
only=all
if [ "${1:-}" = "--only" ]; then
  only=${2:-}
  shift 2 || true
fi
case $only in all | cel | media | paper | coverage | shadows | tumble | gpu | tables) ;; *) echo "report.sh: error: --only takes all, cel, media, paper, coverage, shadows, tumble, gpu or tables, got '$only'" >&2; exit 2 ;; esac
out=docs/report
runs=$out/runs.tsv
command -v gnuplot >/dev/null || { echo "report.sh: error: gnuplot not found (apt-get install gnuplot-nox)" >&2; exit 1; }
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
touch "$runs"

# record FILE SECONDS COMMAND: FILE was produced by COMMAND now, on this machine (replaces FILE's line).
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
cores=$(nproc)
record() {
  { grep -v "^$1	" "$runs" || true; printf '%s\t%s\t%s\t%s\t%s cores of %s\t%s\n' "$1" "$(date -u +%Y-%m-%d)" "$2" "$3" "$cores" "$cpu" "$gl"; } | sort > "$tmp/runs"
  cp "$tmp/runs" "$runs"
}
# provenance FILE: one markdown line saying how FILE was produced (from runs.tsv; a seventh field is
# a note, e.g. that the figures predate a change and are stale).
provenance() {
  awk -F'\t' -v f="$1" '$1 == f {printf "`%s`: `%s`, %s, %s s, on %s; GL: %s.%s\n", $1, $4, $2, $3, $5, $6, (NF >= 7 && $7 != "" ? " **Note:** " $7 "." : ""); found = 1}
                        END {if (!found) printf "`%s`: how it was produced is not recorded.\n", f}' "$runs"
}

if [ "$only" = all ] || [ "$only" = cel ] || [ "$only" = media ]; then
  [ -x "$build/tests/puffbench" ] || { echo "report.sh: error: $build/tests/puffbench not built (cmake --build $build --target puffbench)" >&2; exit 1; }
  start=$(date +%s)
  if [ "$only" = all ]; then
    PUFF_GL=${PUFF_GL:-osmesa} "$build/tests/puffbench" --csv "$tmp/media.csv" --cel-csv "$tmp/cel.csv" --stability-csv "$tmp/stability.csv" "$@" 2> "$tmp/log.txt" || { cat "$tmp/log.txt" >&2; exit 1; }
  elif [ "$only" = cel ]; then
    PUFF_GL=${PUFF_GL:-osmesa} "$build/tests/puffbench" --part cel --cel-csv "$tmp/cel.csv" "$@" 2> "$tmp/log.txt" || { cat "$tmp/log.txt" >&2; exit 1; }
  else
    PUFF_GL=${PUFF_GL:-osmesa} "$build/tests/puffbench" --part media --csv "$tmp/media.csv" --stability-csv "$tmp/stability.csv" "$@" 2> "$tmp/log.txt" || { cat "$tmp/log.txt" >&2; exit 1; }
  fi
  seconds=$(( $(date +%s) - start ))
  gl=$(sed -n '1s/^puffbench: //p' "$tmp/log.txt")
  if [ "$only" = all ]; then
    cmd="PUFF_GL=osmesa $build/tests/puffbench --csv $out/media.csv --cel-csv $out/cel.csv --stability-csv $out/stability.csv${*:+ $*}"
  elif [ "$only" = cel ]; then
    cmd="PUFF_GL=osmesa $build/tests/puffbench --part cel --cel-csv $out/cel.csv${*:+ $*}"
  else
    cmd="PUFF_GL=osmesa $build/tests/puffbench --part media --csv $out/media.csv --stability-csv $out/stability.csv${*:+ $*}"
  fi
  # Keep what puffbench printed (every row, and how long each scene took) beside the CSVs.
  if [ "$only" != media ]; then
    cp "$tmp/cel.csv" "$out/cel.csv"
    record cel.csv "$seconds" "$cmd"
    cp "$tmp/log.txt" "$out/puffbench-cel-log.txt"
  fi
  if [ "$only" != cel ]; then
    cp "$tmp/media.csv" "$out/media.csv"
    cp "$tmp/stability.csv" "$out/stability.csv"
    record media.csv "$seconds" "$cmd"
    record stability.csv "$seconds" "$cmd"
    cp "$tmp/log.txt" "$out/puffbench-media-log.txt"
  fi
fi
if [ "$only" = all ] || [ "$only" = paper ]; then
  # Umenhoffer et al.'s Table 1 and Fig. 12, with the error against the exact reference added.
  [ -x "$build/tests/puff_bench_media" ] || { echo "report.sh: error: $build/tests/puff_bench_media not built" >&2; exit 1; }
  start=$(date +%s)
  PUFF_GL=${PUFF_GL:-osmesa} "$build/tests/puff_bench_media" --reps 5 --csv "$tmp/paper.csv" 2> "$tmp/log-paper.txt" || { cat "$tmp/log-paper.txt" >&2; exit 1; }
  gl=$(sed -n '1s/^puff_bench_media: //p' "$tmp/log-paper.txt")
  cp "$tmp/paper.csv" "$out/paper.csv"
  record paper.csv "$(( $(date +%s) - start ))" "PUFF_GL=osmesa $build/tests/puff_bench_media --reps 5 --csv $out/paper.csv"
fi
if [ "$only" = all ] || [ "$only" = coverage ]; then
  [ -x "$build/tests/puff_bench_coverage" ] || { echo "report.sh: error: $build/tests/puff_bench_coverage not built" >&2; exit 1; }
  start=$(date +%s)
  PUFF_GL=${PUFF_GL:-osmesa} "$build/tests/puff_bench_coverage" --reps 7 --csv "$tmp/coverage.csv" 2> "$tmp/log-coverage.txt" || { cat "$tmp/log-coverage.txt" >&2; exit 1; }
  gl=$(sed -n '1s/^puff_bench_coverage: //p' "$tmp/log-coverage.txt")
  cp "$tmp/coverage.csv" "$out/coverage.csv"
  record coverage.csv "$(( $(date +%s) - start ))" "PUFF_GL=osmesa $build/tests/puff_bench_coverage --reps 7 --csv $out/coverage.csv"
fi
if [ "$only" = gpu ]; then
  start=$(date +%s)
  bash tests/bench/gpu.sh pack "$build" "$tmp/gpu-package" >/dev/null
  bash "$tmp/gpu-package/gpu.sh" run --reps 3 --warm-up 1 --max-frame-s 2 --counts 1000,10000 --sizes 512 --csv "$tmp/llvmpipe.csv" 2> "$tmp/log-gpu.txt" || { cat "$tmp/log-gpu.txt" >&2; exit 1; }
  gl=$(sed -n '1s/^puff_gpubench: //p' "$tmp/log-gpu.txt")
  mkdir -p "$out/gpu"
  cp "$tmp/llvmpipe.csv" "$out/gpu/llvmpipe.csv"
  record gpu/llvmpipe.csv "$(( $(date +%s) - start ))" "bash tests/bench/gpu.sh pack $build; bash $build/gpu-package/gpu.sh run --reps 3 --warm-up 1 --max-frame-s 2 --counts 1000,10000 --sizes 512 --csv $out/gpu/llvmpipe.csv"
fi
if [ "$only" = shadows ]; then
  [ -x "$build/tests/puffbench" ] || { echo "report.sh: error: $build/tests/puffbench not built" >&2; exit 1; }
  start=$(date +%s)
  PUFF_GL=${PUFF_GL:-osmesa} "$build/tests/puffbench" --part shadows --shadow-csv "$tmp/shadows.csv" "$@" 2> "$tmp/log-shadows.txt" || { cat "$tmp/log-shadows.txt" >&2; exit 1; }
  gl=$(sed -n '1s/^puffbench: //p' "$tmp/log-shadows.txt")
  cp "$tmp/shadows.csv" "$out/shadows.csv"
  cp "$tmp/log-shadows.txt" "$out/puffbench-shadows-log.txt"
  record shadows.csv "$(( $(date +%s) - start ))" "PUFF_GL=osmesa $build/tests/puffbench --part shadows --shadow-csv $out/shadows.csv${*:+ $*}"
fi
if [ "$only" = tumble ]; then
  [ -x "$build/tests/puffbench" ] || { echo "report.sh: error: $build/tests/puffbench not built" >&2; exit 1; }
  start=$(date +%s)
  PUFF_GL=${PUFF_GL:-osmesa} "$build/tests/puffbench" --part tumble --tumble-csv "$tmp/tumble.csv" "$@" 2> "$tmp/log-tumble.txt" || { cat "$tmp/log-tumble.txt" >&2; exit 1; }
  gl=$(sed -n '1s/^puffbench: //p' "$tmp/log-tumble.txt")
  cp "$tmp/tumble.csv" "$out/tumble.csv"
  cp "$tmp/log-tumble.txt" "$out/puffbench-tumble-log.txt"
  record tumble.csv "$(( $(date +%s) - start ))" "PUFF_GL=osmesa $build/tests/puffbench --part tumble --tumble-csv $out/tumble.csv${*:+ $*}"
fi
for f in media.csv cel.csv stability.csv paper.csv; do
  [ -s "$out/$f" ] || { echo "report.sh: error: $out/$f is missing: run with --only all first" >&2; exit 1; }
done

# chart NAME [SIZE (900,600)]: draws $tmp/NAME.svg with the gnuplot commands on stdin, which come after
# the terminal, the output file and the CSV separator.
chart() {
  {
    echo "set terminal svg size ${2:-900,600} font 'sans,11'"
    echo "set output \"$tmp/$1.svg\""
    echo 'set datafile separator ","'
    cat
  } | gnuplot
}

# One chart per scene: worst RMSE (log) against median frame time, one series per method, each point
# labelled with its layer resolution; the Pareto front drawn through.
for scene in $(tail -n +2 "$out/media.csv" | cut -d, -f1 | sort -u); do
  grep "^$scene," "$out/media.csv" > "$tmp/$scene.dat"
  awk -F, '$11 == 1' "$tmp/$scene.dat" | sort -t, -k6,6g > "$tmp/$scene.front"
  chart "$scene" <<GP
set title "$scene: error against the exact reference vs frame time (labels: media layer resolution)"
set xlabel "median frame time, ms (this machine)"
set ylabel "worst RMSE over 3 frames, linear colour"
set logscale y
set grid
set key top right
plot for [m in "planar planar-textured soft-linear soft-scurve spherical"] "$tmp/$scene.dat" using (stringcolumn(2) eq m ? \$6 : 1/0):9 with points pt 7 ps 1.3 title m, \
     "$tmp/$scene.dat" using 6:9:(sprintf("%g", \$3)) with labels offset 1.2,0.6 font ",8" notitle, \
     "$tmp/$scene.front" using 6:9 with lines lw 1.5 dt 2 lc rgb "#555555" title "Pareto front"
GP
done

# The cel charts. Per scene: RMSE against frame time for the nailboards over atlas cell size and mesh
# detail, the fixed-function path over mesh detail and the nailboards within the fixed path's limits;
# for a scene of oriented puffs, the ways of turning them.
for scene in $(tail -n +2 "$out/cel.csv" | awk -F, '$3 != "count"' | cut -d, -f1 | sort -u); do
  grep "^$scene," "$out/cel.csv" > "$tmp/cel-$scene.dat"
  chart "cel-$scene" <<GP
set title "$scene (cel): error against the cel reference vs frame time (labels: atlas cell texels / mesh faces / tumble)"
set xlabel "median frame time, ms (this machine)"
set ylabel "worst RMSE over 3 frames, scene-linear colour"
set grid
set key top right
plot "$tmp/cel-$scene.dat" using (stringcolumn(2) eq "cel" && stringcolumn(3) eq "atlas" ? \$9 : 1/0):12 with linespoints pt 7 ps 1.3 title "nailboards, atlas cell size", \
     "$tmp/cel-$scene.dat" using (stringcolumn(2) eq "cel" && stringcolumn(3) eq "lod" ? \$9 : 1/0):12 with points pt 5 ps 1.3 title "nailboards, mesh detail baked", \
     "$tmp/cel-$scene.dat" using (stringcolumn(2) eq "fixed" ? \$9 : 1/0):12 with points pt 9 ps 1.5 title "fixed function, mesh detail", \
     "$tmp/cel-$scene.dat" using (stringcolumn(2) eq "cel-fixed-limits" ? \$9 : 1/0):12 with points pt 13 ps 1.5 title "nailboards within the fixed path's limits", \
     "$tmp/cel-$scene.dat" using (stringcolumn(3) eq "tumble" ? \$9 : 1/0):12 with linespoints pt 11 ps 1.3 title "oriented puffs: the blend, the hull from a size on, the hull", \
     "$tmp/cel-$scene.dat" using 9:12:5 with labels offset 1.5,0.6 font ",8" notitle
GP
done
# Particle count (cloud-50k): frame time against particles, both paths, and the floor.
if grep -q ",count," "$out/cel.csv"; then
  grep ",count," "$out/cel.csv" > "$tmp/counts.dat"
  chart "cel-counts" <<GP
set title "cloud-50k: frame time against particle count (labels: RMSE against the reference, where measured)"
set xlabel "particles"
set ylabel "median frame time, ms (this machine)"
set logscale xy
set grid
set key top left
plot "$tmp/counts.dat" using (stringcolumn(2) eq "cel" ? \$4 : 1/0):9 with points pt 7 ps 1.3 title "nailboards", \
     "$tmp/counts.dat" using (stringcolumn(2) eq "fixed" ? \$4 : 1/0):9 with points pt 9 ps 1.5 title "fixed function", \
     "$tmp/counts.dat" using (stringcolumn(2) eq "cel" ? \$4 : 1/0):10 with points pt 1 ps 1.5 lc rgb "#555555" title "fill-rate floor (bare quads)", \
     "$tmp/counts.dat" using 4:9:(stringcolumn(12) eq "nan" ? "" : sprintf("%.3f", \$12)) with labels offset 0,1 font ",8" notitle
GP
fi

# Shadows: shadow-mask IoU against the exact shadows, and frame time, per scene and method.
if [ -s "$out/shadows.csv" ]; then
  tail -n +2 "$out/shadows.csv" > "$tmp/shadows.dat"
  chart "shadows" 1000,600 <<GP
set title "Shadows against the cel reference's exact ones (labels: method, map scale)"
set xlabel "median frame time, ms (this machine)"
set ylabel "shadow-mask IoU (worst of 3 frames)"
set logscale x
set grid
set key bottom right
plot for [s in "cloud-fig8c explosion magic-lamp cloud-10k"] "$tmp/shadows.dat" using (stringcolumn(1) eq s ? \$7 : 1/0):11 with points pt 7 ps 1.3 title s, \
     "$tmp/shadows.dat" using 7:11:(stringcolumn(2) eq "volumes" ? "volumes" : sprintf("map x%g", \$3)) with labels offset 1.5,0.6 font ",8" notitle
GP
fi

# Tumbling puffs: each multi-view atlas's GL memory against its error over the sweep of
# poses, one series per view layout and tumble method (filled: 1 - mean coverage IoU; open: 1 - the
# worst pose's), points labelled with views x cell size (once: both layouts of one grid and cell size
# take the same memory).
if [ -s "$out/tumble.csv" ]; then
  tail -n +2 "$out/tumble.csv" > "$tmp/tumble.dat"
  chart "tumble" 1000,650 <<GP
set title "Tumbling puffs: multi-view atlas memory against error over yaw, pitch and roll (labels: views x cell texels)"
set xlabel "atlas GL texture memory, MiB (core::atlasTextureBytes, every mip level)"
set ylabel "1 - coverage IoU against the cel reference"
set logscale xy
set yrange [0.01:0.4]
set ytics add (0.01, 0.02, 0.03, 0.05, 0.07, 0.15, 0.2, 0.3)
set grid
set key top right
plot "$tmp/tumble.dat" using (stringcolumn(1) eq "oct" && stringcolumn(14) eq "hull" ? \$5 / 1048576 : 1/0):(1 - \$8) with points pt 7 ps 1.3 lc rgb "#1f77b4" title "oct, hull: 1 - mean", \
     "$tmp/tumble.dat" using (stringcolumn(1) eq "oct" && stringcolumn(14) eq "hull" ? \$5 / 1048576 : 1/0):(1 - \$7) with points pt 6 ps 1.3 lc rgb "#1f77b4" title "oct, hull: 1 - worst pose", \
     "$tmp/tumble.dat" using (stringcolumn(1) eq "hemioct" && stringcolumn(14) eq "hull" ? \$5 / 1048576 : 1/0):(1 - \$8) with points pt 5 ps 1.3 lc rgb "#d62728" title "hemioct, hull: 1 - mean", \
     "$tmp/tumble.dat" using (stringcolumn(1) eq "hemioct" && stringcolumn(14) eq "hull" ? \$5 / 1048576 : 1/0):(1 - \$7) with points pt 4 ps 1.3 lc rgb "#d62728" title "hemioct, hull: 1 - worst pose", \
     "$tmp/tumble.dat" using (stringcolumn(1) eq "oct" && stringcolumn(14) eq "blend" ? \$5 / 1048576 : 1/0):(1 - \$8) with points pt 9 ps 1.1 lc rgb "#9ecae1" title "oct, blend: 1 - mean", \
     "$tmp/tumble.dat" using (stringcolumn(1) eq "oct" && stringcolumn(14) eq "blend" ? \$5 / 1048576 : 1/0):(1 - \$7) with points pt 8 ps 1.1 lc rgb "#9ecae1" title "oct, blend: 1 - worst pose", \
     "$tmp/tumble.dat" using (stringcolumn(1) eq "hemioct" && stringcolumn(14) eq "blend" ? \$5 / 1048576 : 1/0):(1 - \$8) with points pt 13 ps 1.1 lc rgb "#fc9272" title "hemioct, blend: 1 - mean", \
     "$tmp/tumble.dat" using (stringcolumn(1) eq "hemioct" && stringcolumn(14) eq "blend" ? \$5 / 1048576 : 1/0):(1 - \$7) with points pt 12 ps 1.1 lc rgb "#fc9272" title "hemioct, blend: 1 - worst pose", \
     "$tmp/tumble.dat" using (\$5 / 1048576):(1 - \$7):(stringcolumn(1) eq "oct" && stringcolumn(14) eq "hull" ? sprintf("%dx%d x %d", \$2, \$2, \$4) : "") with labels offset 0,-1 font ",8" notitle, \
     0.05 with lines dt 2 lc rgb "#555555" title "the bar: coverage IoU 0.95"
GP
fi

# Where the media methods break: the camera flying into smoke, largest and mean second difference.
grep "^smoke-flythrough," "$out/stability.csv" > "$tmp/flight.dat" || true
if [ -s "$tmp/flight.dat" ]; then
  awk -F, '$3 == "largest_second_difference" {l[$2] = $4} $3 == "mean_second_difference" {m[$2] = $4}
           END {for (k in l) print k "," l[k] "," m[k]}' "$tmp/flight.dat" | sort > "$tmp/flight2.dat"
  chart "flight" 900,500 <<GP
set title "Flying into smoke (smoke-flythrough, frozen particles, 96 frames): frame-to-frame second difference"
set ylabel "second difference of frame values"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set boxwidth 0.9
set grid ytics
set key top right
plot "$tmp/flight2.dat" using 2:xtic(1) title "largest (popping)", "" using 3 title "mean"
GP
fi

# Fewer, bigger particles against the full model (cloud-50k): error against frame time.
if grep -q ",fraction," "$out/cel.csv"; then
  grep ",fraction," "$out/cel.csv" > "$tmp/fraction.dat"
  chart "cel-fraction" <<GP
set title "cloud-50k: fewer, bigger particles against the reference of all of them (labels: share)"
set xlabel "median frame time, ms (this machine)"
set ylabel "RMSE against the full model's reference, scene-linear colour"
set grid
set key top right
plot "$tmp/fraction.dat" using (stringcolumn(2) eq "cel" ? \$9 : 1/0):12 with points pt 7 ps 1.3 title "nailboards", \
     "$tmp/fraction.dat" using (stringcolumn(2) eq "fixed" ? \$9 : 1/0):12 with points pt 9 ps 1.5 title "fixed function", \
     "$tmp/fraction.dat" using 9:12:(sprintf("%g", \$4)) with labels offset 1.2,0.6 font ",8" notitle
GP
fi

# Table 1 and Fig. 12 as error against time.
grep "^table1,\(planar\|spherical\)," "$out/paper.csv" > "$tmp/table1.dat"
grep "^fig12," "$out/paper.csv" > "$tmp/fig12.dat"
chart "paper-table1" <<GP
set title "Table 1 redone (512^2, layer 1/2, 4 screens of overdraw): error against frame time (labels: particles)"
set xlabel "median frame ms, pass + compose (this machine)"
set ylabel "RMSE against the exact reference, linear colour"
set grid
set key top left
plot "$tmp/table1.dat" using (stringcolumn(2) eq "planar" ? \$15 : 1/0):21 with points pt 9 ps 1.5 title "planar", \
     "$tmp/table1.dat" using (stringcolumn(2) eq "spherical" ? \$15 : 1/0):21 with points pt 7 ps 1.3 title "spherical", \
     "$tmp/table1.dat" using 15:21:3 with labels offset 1.5,0.6 font ",8" notitle
GP
chart "paper-fig12" <<GP
set title "Fig. 12 redone (1024^2, spherical, 1052 particles): error against time (labels: layer scale)"
set xlabel "median ms (this machine)"
set ylabel "RMSE against the exact reference, linear colour"
set logscale xy
set grid
set key top right
plot "$tmp/fig12.dat" using 16:21 with linespoints pt 7 ps 1.3 title "whole frame (downsample + pass + compose)", \
     "$tmp/fig12.dat" using 13:21 with linespoints pt 5 ps 1.3 title "particle pass alone", \
     "$tmp/fig12.dat" using 16:21:5 with labels offset 1.5,0.6 font ",8" notitle
GP

# Opaque surfaces through the media: the largest step of the error image at the wall, per method.
awk -F, '$3 == "largest_error_jump" {print $1 "," $2 "," $4}' "$out/stability.csv" > "$tmp/jump.dat"
if [ -s "$tmp/jump.dat" ]; then
  awk -F, '$1 == "wall-through-smoke" {w[$2] = $3} $1 == "explosion-walls" {e[$2] = $3}
           END {for (k in w) print k "," w[k] "," e[k]}' "$tmp/jump.dat" | sort > "$tmp/jump2.dat"
  chart "walls" 900,500 <<GP
set title "Walls through the media: largest step of the error image (frame minus exact reference)"
set ylabel "largest neighbour step, linear colour"
set logscale y
set yrange [0.001:1]
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set boxwidth 0.9
set grid ytics
set key top right
plot "$tmp/jump2.dat" using 2:xtic(1) title "wall through a smoke ball", "" using 3 title "explosion-walls (frames 5, 20)"
GP
fi

# The GPU benchmark: every machine's CSV in docs/report/gpu/ (docs/bench/gpu.md), one table row per
# case and samples, one column pair per machine. The time a machine is read by: a GPU's timer query,
# llvmpipe's wall clock (its timer query does not time its rasterizer). gpu_table prints
# "case,samples,MACHINE ms,MACHINE ratio,..." where the ratio is to the floor, or to the baseline
# for the rows that have one (the hull's is the blend, the media's the frame without media).
gpu_table() {
  awk -F, 'FNR == 1 {m = FILENAME; sub(".*/", "", m); sub("[.]csv$", "", m); machines[++nm] = m
                     delete col; for (i = 1; i <= NF; ++i) col[$i] = i; next}
           {key = $col["case"] "," $col["samples"]; if (!(key in seen)) {seen[key] = 1; keys[++nk] = key}
            llvm = index($col["renderer"], "llvmpipe") > 0
            ms[key, m] = llvm ? $col["wall_ms"] : $col["gpu_ms"]
            if ($col["baseline"] != "") r = llvm ? $col["wall_ms"] / $col["baseline_wall_ms"] : $col["gpu_over_baseline"]
            else r = llvm ? $col["wall_over_floor"] : $col["gpu_over_floor"]
            ratio[key, m] = r; base[key] = $col["baseline"] == "" ? "floor" : $col["baseline"]}
           END {printf "case,samples,vs"; for (i = 1; i <= nm; ++i) printf ",%s ms,%s ratio", machines[i], machines[i]; print ""
                for (k = 1; k <= nk; ++k) {printf "%s,%s", keys[k], base[keys[k]]
                  for (i = 1; i <= nm; ++i) {m = machines[i]
                    if ((keys[k], m) in ms) printf ",%.3f,%s", ms[keys[k], m], (ratio[keys[k], m] == "" ? "" : sprintf("%.2f", ratio[keys[k], m]))
                    else printf ",,"}
                  print ""}}' "$@"
}
gpu_csvs=()
[ -d "$out/gpu" ] && mapfile -t gpu_csvs < <(ls "$out"/gpu/*.csv 2>/dev/null)
if [ ${#gpu_csvs[@]} -gt 0 ]; then
  gpu_table "${gpu_csvs[@]}" > "$tmp/gpu.dat"
  machines=$(head -1 "$tmp/gpu.dat" | awk -F, '{print (NF - 3) / 2}')
  for samples in 1 4; do
    awk -F, -v s="$samples" 'NR == 1 {printf "case"; for (i = 5; i <= NF; i += 2) {h = $i; sub(" ratio", "", h); printf ",%s", h}; print ""; next}
                             $2 == s {printf "%s", $1; for (i = 5; i <= NF; i += 2) printf ",%s", ($i == "" ? "NaN" : $i); print ""}' \
      "$tmp/gpu.dat" > "$tmp/gpu-s$samples.dat"
    chart "gpu-s$samples" 1100,600 <<GP
set title "Each case's frame over its floor (the hull over the blend, media over no media), MSAA x$samples"
set ylabel "ratio, within one machine's run"
set logscale y
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.8 border -1
set boxwidth 0.9
set grid ytics
set xtics rotate by -45 font ",8"
set key top left
plot for [i = 2:$((machines + 1))] "$tmp/gpu-s$samples.dat" using i:xtic(1) title columnheader(i)
GP
  done
fi

cp "$tmp"/*.svg "$out/"

# ---- the tables the docs quote, each from one CSV ---------------------------------------------------

# paper_tables CSV: Table 1 and Fig. 12 from a puff_bench_media CSV (columns by name: older CSVs lack
# the planar-textured and floor columns, which are then left empty).
paper_tables() {
  echo "**Table 1** (one row per particle count and method; median ms; ratios within the run; RMSE in"
  echo "linear colour against \`reference::renderMediaReference\` over the same opaque layer, clamped to"
  echo "[0, 1] as the bench's 8-bit target is):"
  echo
  echo "| particles | method | radius | frame ms | pass ms | compose ms | frame / planar | pass / planar | frame / planar-textured | pass / planar-textured | pass / floor | RMSE |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  awk -F, 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
           function v(name) {return (name in col) ? $col[name] : ""}
           $1 == "table1" {printf "| %s | %s | %s | %.1f | %.1f | %.1f | %s | %s | %s | %s | %s | %s |\n", v("particles"), v("method"),
             (v("radius") + 0 > 0 ? v("radius") : "-"), v("frame_ms"), v("pass_ms"), v("compose_ms"),
             v("frame_ratio_to_planar"), v("pass_ratio_to_planar"), v("frame_ratio_to_planar_textured"),
             v("pass_ratio_to_planar_textured"), v("pass_ratio_to_floor"), v("rmse_vs_reference")}' "$1"
  echo
  echo "**Fig. 12** (spherical; median ms; speedups over layer scale 1 of the same run):"
  echo
  echo "| layer scale | layer px | pass ms | downsample ms | compose ms | whole frame ms | pass speedup | frame speedup | RMSE |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  awk -F, 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
           function v(name) {return (name in col) ? $col[name] : ""}
           $1 == "fig12" {printf "| %s | %s | %.1f | %.1f | %.1f | %.1f | %s | %s | %s |\n", v("layer_scale"), v("layer_px"),
             v("pass_ms"), v("downsample_ms"), v("compose_ms"), v("total_ms"), v("pass_speedup_over_scale1"),
             v("total_speedup_over_scale1"), v("rmse_vs_reference")}' "$1"
}

# media_budget CSV: per scene, the scene's own method at each layer resolution (what puffrender
# --max-error measures), with where the error lies and, when measured, against the physical reference.
media_budget() {
  if ! head -1 "$1" | grep -q scene_method; then
    echo "Pending: \`$1\` predates the region and physical columns (scene_method, worst_rmse_media, ...)."
    return
  fi
  echo "Per scene, its own method (the one \`puffrender --max-error\` keeps) at each media layer resolution;"
  echo "the worst over the first, middle and last frame of its camera path. RMSE in scene-linear colour,"
  echo "not clamped. *media*: over the pixels where the reference shows a medium; *band*: within 2 pixels"
  echo "of where a particle meets a surface or the near plane; SSIM over the whole frame (1: the same)."
  echo "*model*: against \`reference::renderMediaReference\` (the model, exactly: what \`--max-error\`"
  echo "chooses by, first column); *physical*: against \`reference::renderMediaPhysical\` (the particles as"
  echo "one continuous medium; empty where not measured, i.e. without \`puffbench --physical\`)."
  echo
  echo "| scene | method | size | resolution | frame ms | RMSE | media | band | SSIM | physical RMSE | media | band | SSIM |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
  awk -F, 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
           function v(name) {return (name in col) ? $col[name] : ""}
           function e(x) {return x == "" ? "" : sprintf(x + 0 >= 0.001 || x + 0 == 0 ? "%.4f" : "%.2g", x)}
           v("scene_method") == 1 {printf "| %s | %s | %sx%s | %s | %.1f | %s | %s | %s | %.4f | %s | %s | %s | %s |\n",
             v("scene"), v("method"), v("width"), v("height"), v("resolution"), v("median_ms"), e(v("worst_rmse")),
             e(v("worst_rmse_media")), e(v("worst_rmse_band")), v("worst_ssim"), e(v("worst_rmse_physical")),
             e(v("worst_rmse_media_physical")), e(v("worst_rmse_band_physical")),
             (v("worst_ssim_physical") == "" ? "" : sprintf("%.4f", v("worst_ssim_physical")))}' "$1"
}

generated() { echo "<!-- Generated by tests/bench/report.sh from $1: do not edit; run \`tests/bench/report.sh --only tables\` -->"; }

{
  generated "$out/media.csv"
  echo
  provenance media.csv
  echo
  media_budget "$out/media.csv"
} > "$out/media-budget.md"
{
  generated "$out/paper.csv"
  echo
  provenance paper.csv
  echo
  paper_tables "$out/paper.csv"
} > "$out/paper-tables.md"
if [ -s "$out/coverage.csv" ]; then
  {
    generated "$out/coverage.csv"
    echo
    provenance coverage.csv
    echo
    echo "The media passes over what the media cover (\`covered\`, the default) and over the whole frame"
    echo "(\`whole-frame\`, as before coverage), beside the same frame without its media (\`no-media\`): median"
    echo "frame ms (the draw and its read-back, less the simulators' time), ratios within the run"
    echo "(docs/media.md, \"Cost follows coverage\")."
    echo
    echo "| case | frame | size | samples | media particles | covered | no media ms | whole frame ms | covered ms | covered / no media | whole frame / no media | covered / whole frame |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    awk -F, 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
             function v(name) {return $col[name]}
             v("variant") == "covered" {printf "| %s | %s | %s x %s | %s | %s | %.1f %% | %s | %s | %s | %s | %.3f | %s |\n", v("case"), v("frame"),
               v("width"), v("height"), v("samples"), v("media_particles"), 100 * v("covered_share"), v("no_media_ms"),
               v("whole_frame_ms"), v("ms"), v("ratio_to_no_media"), v("whole_frame_ms") / v("no_media_ms"), v("ratio_to_whole_frame")}' "$out/coverage.csv"
  } > "$out/coverage.md"
fi
# Where the tumbling hull's time goes (tests/bench/hull_costs.sh): each variant's hull against its blend.
hull_costs=docs/bench/hull-costs-llvmpipe-2core.csv
if [ -s "$hull_costs" ]; then
  {
    generated "$hull_costs"
    echo
    echo "From \`$hull_costs\` (\`bash tests/bench/hull_costs.sh --reps 3 --warm-up 1 --csv FILE\`; docs/bench/README.md"
    echo "says where it ran): dust-roll's frames 30-35 at 960 x 540, MSAA 1, every puff oriented, drawn by the hull"
    echo "with one phase of its march left out at a time (tests/bench/hull_costs.sh names them), beside the blend"
    echo "in the same rounds. Median wall ms a frame (llvmpipe), and what the phase costs: the hull's frame as it is"
    echo "less the variant's."
    echo
    echo "| variant | hull ms | blend ms | hull / blend | the phase's share of the hull's frame |"
    echo "| --- | --- | --- | --- | --- |"
    awk -F, 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
             $col["case"] == "hull" {v[++n] = $col["variant"]; h[n] = $col["wall_ms"]; b[n] = $col["baseline_wall_ms"]}
             END {for (i = 1; i <= n; ++i) printf "| %s | %.0f | %.0f | %.1f | %s |\n", v[i], h[i], b[i], h[i] / b[i],
                    (v[i] == "as-is" ? "" : sprintf("%.0f %%", 100 * (h[1] - h[i]) / h[1]))}' "$hull_costs"
  } > "$out/hull-costs.md"
fi
# The cel nailboards and frames against the fill-rate floor (docs/bench/README.md and
# docs/cel-rendering.md link it).
cel_bench=docs/bench/cel-llvmpipe-2core.csv
if [ -s "$cel_bench" ]; then
  {
    generated "$cel_bench"
    echo
    echo "From \`$cel_bench\` (\`PUFF_GL=osmesa build/tests/puff_bench_cel --reps 5 --max-frame-s 60 --csv FILE\`;"
    echo "docs/bench/README.md says where it ran and what each method draws). Median ms a frame, and in brackets"
    echo "the ratio to the fill-rate floor of the same count and size, all in one run."
    echo
    echo "| particles | target | floor | nailboards (each pixel shaded once) | nailboards, every layer shaded | depth only | full-map (casters + lit) | full-volumes | of which the volume pass |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    awk -F, 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
             {k = $col["particles"] "|" $col["size"]; if (!(k in seen)) {seen[k] = 1; order[++n] = k}
              ms[k, $col["method"]] = $col["median_ms"]; x[k, $col["method"]] = $col["ratio_to_floor"]}
             function cell(k, m) {return ms[k, m] == "" ? "-" : sprintf("%.0f (%.1fx)", ms[k, m], x[k, m])}
             END {for (i = 1; i <= n; ++i) {k = order[i]; split(k, a, "|")
                    printf "| %s | %s^2 | %.1f | %s | %s | %s | %s = %.0f + %.0f | %s | %s |\n", a[1], a[2], ms[k, "floor"],
                           cell(k, "nailboards"), cell(k, "nailboards.every-layer"), cell(k, "nailboards.depth"),
                           cell(k, "full-map"), ms[k, "full-map.casters"], ms[k, "full-map.lit"], cell(k, "full-volumes"),
                           cell(k, "full-volumes.volumes")}}' "$cel_bench"
  } > "$out/cel-bench.md"
fi
# The tumble sweep's two methods side by side, accuracy and time (docs/cel-rendering.md quotes it).
if [ -s "$out/tumble.csv" ]; then
  {
    generated "$out/tumble.csv"
    echo
    echo "From \`tumble.csv\` (\`tests/bench/report.sh --only tumble\`; the run's command, machine and date are in"
    echo "\`runs.tsv\`): every pose of \`eval::tumblePoses(15)\`, one puff 48 px across, against the cel reference"
    echo "of the turned meshes. IoU worst pose / mean; frame ms: the median of one frame of the pose grid (24 x 13"
    echo "puffs at 1728 x 936, nailboards only), llvmpipe, so compare times within the run only."
    echo
    echo "| atlas | cell texels | hull: coverage IoU | hull: outline IoU | blend: coverage IoU | blend: outline IoU | hull ms | blend ms | hull / blend |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    awk -F, 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
             {k = $col["layout"] " " $col["grid"] "x" $col["grid"] "|" $col["cell_size"]
              if (!(k in seen)) {seen[k] = 1; order[++n] = k}
              m = $col["method"]
              cov[k, m] = sprintf("%.3f / %.3f", $col["coverage_iou_min"], $col["coverage_iou_mean"])
              ink[k, m] = sprintf("%.3f / %.3f", $col["outline_iou_min"], $col["outline_iou_mean"])
              ms[k, m] = $col["median_ms"]}
             END {for (i = 1; i <= n; ++i) {k = order[i]; split(k, a, "|")
                    ratio = (ms[k, "blend"] > 0 && ms[k, "hull"] != "") ? sprintf("%.1f", ms[k, "hull"] / ms[k, "blend"]) : ""
                    printf "| %s | %s | %s | %s | %s | %s | %.0f | %.0f | %s |\n", a[1], a[2], cov[k, "hull"], ink[k, "hull"],
                           cov[k, "blend"], ink[k, "blend"], ms[k, "hull"], ms[k, "blend"], ratio}}' "$out/tumble.csv"
  } > "$out/tumble-table.md"
fi
if [ ${#gpu_csvs[@]} -gt 0 ]; then
  {
    echo "# The GPU benchmark, machine beside machine"
    echo
    echo "Generated by tests/bench/report.sh from $(for f in "${gpu_csvs[@]}"; do printf '`%s` ' "$f"; done)(docs/bench/gpu.md"
    echo "says what each case is). Per machine: the median frame ms (a GPU's timer query; llvmpipe's wall"
    echo "clock, as its timer query does not time its rasterizer) and the ratio to what the row is measured"
    echo "against (\`vs\`): its fill-rate floor, the blend for the hull, the frame without media for the media."
    echo "Ratios compare within one machine's run only. Charts: [MSAA x1](gpu-s1.svg), [MSAA x4](gpu-s4.svg)."
    echo
    for f in "${gpu_csvs[@]}"; do provenance "${f#"$out"/}"; echo; done
    awk -F, 'NR == 1 {printf "|"; for (i = 1; i <= NF; ++i) printf " %s |", $i; print ""; printf "|"; for (i = 1; i <= NF; ++i) printf " --- |"; print ""; next}
             {printf "|"; for (i = 1; i <= NF; ++i) printf " %s |", $i; print ""}' "$tmp/gpu.dat"
  } > "$out/gpu.md"
fi
if [ -s docs/bench/media-llvmpipe-2core.csv ]; then
  {
    generated docs/bench/media-llvmpipe-2core.csv
    echo
    echo "From \`docs/bench/media-llvmpipe-2core.csv\`: the command, machine and date are in docs/bench/README.md's table of files."
    echo
    paper_tables docs/bench/media-llvmpipe-2core.csv
  } > docs/bench/media-tables.md
fi

{
  echo "# Speed against accuracy"
  echo
  echo "Generated by \`tests/bench/report.sh\` (\`--only all\` reruns every benchmark but the shadow and tumble"
  echo "sweeps, \`--only cel\`, \`--only media\`, \`--only shadows\` and \`--only tumble\` puffbench's parts,"
  echo "\`--only paper\` puff_bench_media, \`--only gpu\` the GPU benchmark, \`--only tables\` only rewrites this"
  echo "page, the charts and the tables from the CSVs). Each CSV here came from one command; \`runs.tsv\`"
  echo "keeps which, when and where:"
  echo
  for f in cel.csv media.csv stability.csv paper.csv; do echo "- $(provenance $f)"; done
  [ -s "$out/shadows.csv" ] && echo "- $(provenance shadows.csv)"
  [ -s "$out/tumble.csv" ] && echo "- $(provenance tumble.csv)"
  echo
  echo "Times are that machine's (a software rasterizer, not a GPU): compare them within one CSV. No"
  echo "test fails on these numbers; they are measurements."
  echo
  if [ ${#gpu_csvs[@]} -gt 0 ]; then
    echo "The GPU benchmark (\`--only gpu\` runs it on this machine's llvmpipe; docs/bench/gpu.md carries it to a"
    echo "GPU) is [gpu.md](gpu.md): each machine's frame costs over their floors, side by side."
    echo
  fi
  echo "# The cel path: nailboards and the fixed-function path"
  echo
  echo "**The reference** (\`puffrender --path reference\`, \`RenderPath::kReference\`): every particle"
  echo "drawn as its actual puff mesh (the atlas's source mesh, full detail), placed and turned as its"
  echo "billboard, Eq. 2 per pixel with the same ambient, colour, light and ramp; ink the outline's"
  echo "width around each puff's true outer silhouette (its silhouette edges, at their depth); shadows"
  echo "from a 4096-texel shadow map of the meshes that knows which puff each texel saw (a puff is"
  echo "shadowed by every other one, never by itself), not cut at \`shadowLength\`; 3 x 3 supersampled."
  echo "Tests: \`tests/unit/cel_reference_test.cpp\` (a sphere puff is a disc of its size, q(N.L) of the"
  echo "sphere's normals, the ink ring's width, the ground shadow the light's projection)."
  echo
  echo "**What each point is.** x: the median wall time of a whole frame (\`renderFrame\`: clear, opaque"
  echo "pass, particles, shadows, read-back) over three frames of the scene (first, middle, last), 320 x"
  echo "240 unless the command says otherwise. \`floor_ms\` in \`cel.csv\` is the fill-rate floor, measured"
  echo "in the same run: the same frames with every particle a bare alpha-tested quad of its nailboard's"
  echo "size (\`SceneRenderer::setFillRateFloor\`); \`ratio_to_floor\` divides by it. The fixed path's rows"
  echo "divide by its own floor: its billboards as GL 1.x bare alpha-tested quads, within its limits"
  echo "(\`fixedfunc::FixedRenderer::drawFloorFrame\`; CSVs made before it divide them by the"
  echo "programmable floor, which they could beat). \`bare_ms\` is the frame without particles (that path's own). y: the worst RMSE"
  echo "over those frames of the scene-linear frame values (\`renderFrame\`, not clamped) against the reference of the same particles, over"
  echo "the whole frame (as \`puffrender --max-error\` measures it); \`cel.csv\` adds the RMSE over the"
  echo "pixels where either image shows puffs (\`rmse_puffs\`), the coverage IoU (pixels off each"
  echo "path's own bare frame by 1/64) and the outline IoU (ink pixels). Atlas points: the scene's puffs re-baked at 64 to 1024 texels a cell. Mesh-detail"
  echo "points: the atlas (256 texels) baked from the meshes decimated to 1, 1/4, 1/16, 1/64 of their"
  echo "faces (labels: faces of all variations), and the fixed path drawing its puff mesh decimated"
  echo "alike (labels: that mesh's faces); the reference keeps the full meshes. The fixed path and"
  echo "\"nailboards within the fixed path's limits\" are measured against the reference of the scene"
  echo "restricted to those limits (no shadows, uniform ambient, view-plane billboards)."
  echo
  echo "How to read it: where the error stops falling as the cells grow, what is left is the nailboards'"
  echo "own error, mostly their ink. The band is drawn from the baked distance map, and where that runs"
  echo "out (\`distanceRange\` texels from the silhouette: on a puff a few pixels wide) from the radius"
  echo "table, so small puffs keep an ink band and their size (before that change cloud-50k at 263"
  echo "particles had outline IoU 0 and coverage IoU 0.55); see \`outline_iou\` and \`coverage_iou\`."
  echo "Mesh detail costs the nailboards nothing at run time (it is baked), and its error grows as faces"
  echo "fall; the fixed path draws its mesh every frame, so there fewer faces are faster."
  echo
  if grep -q ",tumble," "$out/cel.csv"; then
    echo "Tumble points (\`puffbench --tumble-scenes\`: dust-roll at its own 480 x 320, its first, middle and"
    echo "last frames measured as above): its oriented puffs turned by the blend, by the hull only for puffs at"
    echo "least the labels' size across (\`style.hullFromPixels\`, the blend for the rest), and by the hull on"
    echo "all: what \`puffrender --max-error\` chooses among (docs/cel-rendering.md, \"Hull or blend, puff by puff\")."
    echo
  fi
  for scene in $(tail -n +2 "$out/cel.csv" | awk -F, '$3 != "count"' | cut -d, -f1 | sort -u); do
    echo "## $scene (cel)"
    echo
    echo "![$scene cel](cel-$scene.svg)"
    echo
    echo "| path | parameter | value | frame ms | x floor | worst RMSE | RMSE on puffs | coverage IoU | outline IoU | Pareto |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    grep "^$scene," "$out/cel.csv" | awk -F, '{printf "| %s | %s | %s | %.1f | %s | %.4f | %.4f | %.3f | %.3f | %s |\n", $2, $3, $5, $9, ($11 == "" ? "below floor" : sprintf("%.2f", $11)), $12, $17, $14, $15, ($16 == 1 ? "yes" : "")}'
    echo
  done
  if grep -q ",count," "$out/cel.csv"; then
    echo "## Particle count (cloud-50k, frame 0)"
    echo
    echo "![particle count](cel-counts.svg)"
    echo
    echo "The scene's emitters scaled to each count (a scene's first N particles are the same whatever"
    echo "its count). Error only up to the reference limit (\`--reference-limit\`, 12,500 by default; the"
    echo "command above says what this run used): a row above it has \`nan\`, not measured."
    echo "\`puffbench-cel-log.txt\` says how long each count took, its references included."
    echo
    awk -F, '$3 == "count" && $14 != "nan" {k = $2; n[k]++; if (!(k in cmin) || $14 < cmin[k]) {cmin[k] = $14; cat[k] = $4}
                                          if (!(k in omin) || $15 < omin[k]) {omin[k] = $15; oat[k] = $4}}
             END {for (k in n) printf "- %s: at the %d counts measured, coverage IoU at least %.4f (%s particles), outline IoU at least %.4f (%s particles).\n",
                    (k == "cel" ? "Nailboards" : "Fixed function"), n[k], cmin[k], cat[k], omin[k], oat[k]}' "$out/cel.csv" | sort -r
    echo
    echo "| path | particles | frame ms | fill-rate floor ms | x floor | RMSE | RMSE on puffs | coverage IoU | outline IoU |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    grep ",count," "$out/cel.csv" | awk -F, '{printf "| %s | %s | %.1f | %.2f | %s | %s | %s | %s | %s |\n", $2, $4, $9, $10, ($11 == "" ? "below floor" : sprintf("%.1f", $11)), $12, $17, $14, $15}'
    echo
  fi
  if [ -s "$out/shadows.csv" ]; then
    echo "## Shadows: the map and the volumes against the exact shadows"
    echo
    echo "![shadows](shadows.svg)"
    echo
    echo "\`puffbench --part shadows\`: each method on each scene (shadows on; cloud-10k is cloud-50k's"
    echo "emitters scaled to 10,000 puffs). Shadow-mask IoU: the pixels a frame's shadows darken (a channel"
    echo "0.02 darker than the same path's frame without shadows) against those the cel reference's exact"
    echo "shadows darken; RMSE against the reference's frame (display values). Worst of the first, middle"
    echo "and last frame; times are medians, the fill-rate floor the same particles as bare quads."
    echo
    echo "| scene | method | map scale | frame ms | x floor | no shadows ms | shadow IoU | RMSE |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
    tail -n +2 "$out/shadows.csv" | awk -F, '{printf "| %s | %s | %s | %.1f | %s | %.1f | %.3f | %.4f |\n", $1, $2, ($2 == "map" ? $3 : ""), $7, ($9 == "" ? "below floor" : sprintf("%.1f", $9)), $10, $11, $12}'
    echo
  fi
  if grep -q ",fraction," "$out/cel.csv"; then
    echo "## Fewer, bigger particles (cloud-50k, frame 0)"
    echo
    echo "![particle fraction](cel-fraction.svg)"
    echo
    echo "What \`--max-error\` chooses for a scene's particle count (\`particleFraction\`): the first"
    echo "share of each emitter's particles, each (1/share)^(1/3) larger so they fill about the same"
    echo "volume, measured against the reference of ALL the particles (the largest count above with a"
    echo "reference). Fewer particles are cheaper; how much error each saving costs is the chart."
    echo
    echo "| path | share | particles | frame ms | x floor | RMSE vs all | coverage IoU | outline IoU |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
    grep ",fraction," "$out/cel.csv" | awk -F, '{printf "| %s | %s | %s | %.1f | %s | %s | %s | %s |\n", $2, $5, $6, $9, ($11 == "" ? "below floor" : sprintf("%.1f", $11)), $12, $14, $15}'
    echo
  fi
  if [ -s "$out/tumble.csv" ]; then
    echo "## Tumbling puffs: the multi-view atlas's size against its accuracy (\`tumble.csv\`)"
    echo
    echo "![tumbling puffs](tumble.svg)"
    echo
    echo "\`tests/bench/report.sh --only tumble\` (\`puffbench --part tumble\`, \`tests/bench/puffbench_tumble.cpp\`): the"
    echo "art's four puffs (\`art/puffs/variation-{1.obj,2.ply,3.off,4.stl}\`) baked with each view layout"
    echo "(*oct*: views over the whole sphere; *hemioct*: the front hemisphere, back views mirrored), grid"
    echo "(grid x grid views a variation) and cell size. Each atlas's oriented nailboards, drawn by each"
    echo "tumble method (\`style.tumble\`: *hull*, the eye ray marched through the hull of the views;"
    echo "*blend*, four views turned and blended; docs/cel-rendering.md, \"Tumbling puffs\"), are turned through"
    echo "every pose of \`eval::tumblePoses(15)\` (yaw and roll every 15 degrees around the circle, pitch"
    echo "every 15 from -90 to 90; one puff 48 pixels across per pose, orthographic, outlines 2 pixels,"
    echo "Eq. 2 shading, no shadows) and compared pose by pose with one cel reference of the same poses"
    echo "(\`eval::renderTumbleReference\`: the actual meshes turned; it depends on the meshes and the sweep,"
    echo "not the atlas, so it is drawn once). Atlas memory: \`core::atlasTextureBytes\` of the baked atlas,"
    echo "what the GL holds (every mip level). Coverage IoU: the puff's pixels, ink included, against the"
    echo "reference's; outline IoU: the ink alone, the pixels the outlines add (each frame drawn again"
    echo "without outlines, for both); the worst pose, the mean, and the share of poses"
    echo "at the bars (coverage >= 0.95, outline >= 0.5). Frame ms: the median time of one frame of the"
    echo "pose grid (one roll: 24 x 13 puffs at 1728 x 936), nailboards only."
    echo
    echo "| layout | views | cell texels | method | atlas MiB | poses | coverage IoU worst | mean | share >= 0.95 | outline IoU worst | mean | share >= 0.5 | frame ms |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    tail -n +2 "$out/tumble.csv" | awk -F, '{printf "| %s | %dx%d | %d | %s | %.1f | %d | %.4f | %.4f | %.3f | %.4f | %.4f | %.3f | %.0f |\n", $1, $2, $2, $4, $14, $5 / 1048576, $6, $7, $8, $9, $10, $11, $12, $13}'
    echo
    tail -n +2 "$out/tumble.csv" | awk -F, '$7 >= 0.95 && $10 >= 0.5 {n++; if (!best || $5 < bytes) {best = $1 " " $2 "x" $2 " x " $4 " (" $14 ")"; bytes = $5}}
      END {if (n) printf "Atlases with every pose at both bars: %d; the smallest, %s, %.1f MiB.\n", n, best, bytes / 1048576;
           else print "No atlas here has every pose at both bars (coverage IoU >= 0.95 and outline IoU >= 0.5)."}'
    echo
    # The run's own figures, from the CSV: each method's worst and mean poses over the atlases, and the
    # grid frame's hull against the blend atlas by atlas.
    tail -n +2 "$out/tumble.csv" | awk -F, '
      function lo(k, v) { if (!(k in mn) || v < mn[k]) mn[k] = v }
      function hi(k, v) { if (!(k in mx) || v > mx[k]) mx[k] = v }
      { m = $14; lo(m "c", $7); hi(m "c", $7); lo(m "o", $10); hi(m "o", $10); lo(m "cm", $8); hi(m "cm", $8)
        lo(m "om", $11); hi(m "om", $11); key = $1 " " $2 " " $4; ms[key, m] = $13; keys[key] = 1 }
      END {
        for (k in keys) if (ms[k, "blend"] > 0) { r = ms[k, "hull"] / ms[k, "blend"]; lo("r", r); hi("r", r) }
        printf "Over the atlases of this run: the hull'"'"'s worst pose is %.3f to %.3f coverage IoU and %.3f to %.3f\n", mn["hullc"], mx["hullc"], mn["hullo"], mx["hullo"]
        printf "outline IoU (its means %.3f to %.3f and %.3f to %.3f); the blend'"'"'s worst %.3f to %.3f and %.3f\n", mn["hullcm"], mx["hullcm"], mn["hullom"], mx["hullom"], mn["blendc"], mx["blendc"], mn["blendo"]
        printf "to %.3f. A grid frame takes the hull %.1f to %.1f times the blend'"'"'s time. What holds the hull'"'"'s\n", mx["blendo"], mn["r"], mx["r"]
        print "worst poses there, and where its time goes: docs/cel-rendering.md, \"Tumbling puffs\", and"
        print "[hull-costs.md](hull-costs.md)."
      }'
    echo
  fi
  echo "# The media path: fire, smoke and dust"
  echo
  echo "## Umenhoffer et al.'s Table 1 and Fig. 12, with the error added (\`paper.csv\`)"
  echo
  echo "\`build/tests/puff_bench_media\` (docs/bench/README.md says how it is set up): an explosion-like"
  echo "ball of fire, smoke and dust cut by a floor and a wall; each case once more with heat shimmer off,"
  echo "read back and compared with \`puff::reference::renderMediaReference\` over the same opaque layer."
  echo
  echo "![Table 1](paper-table1.svg)"
  echo
  tail -n +3 "$out/paper-tables.md"
  echo
  echo "![Fig. 12](paper-fig12.svg)"
  echo
  echo "## Where the methods break (\`stability.csv\`)"
  echo
  echo "![flying into smoke](flight.svg)"
  echo
  echo "The camera of smoke-flythrough flies into the smoke (its particles frozen as they are at frame"
  echo "0, so births do not pop; the pillar taken out, 160 x 120), every frame drawn in order; the bars"
  echo "are the largest and the mean of |f[k+1] - 2 f[k] + f[k-1]| over pixels and channels"
  echo "(\`reference::largestSecondDifference\`). A planar or soft billboard vanishes at once when the"
  echo "near plane passes its centre: the spike. The spherical billboard's opacity follows the ray's"
  echo "path, which shrinks smoothly. The tests assert the same on a controlled flight"
  echo "(\`media_scene_test\`, planar 0.92 against spherical 0.059)."
  echo
  echo "| scene | method | metric | value |"
  echo "| --- | --- | --- | --- |"
  tail -n +2 "$out/stability.csv" | awk -F, '{printf "| %s | %s | %s | %.4f |\n", $1, $2, $3, $4}'
  echo
  echo "![walls through the media](walls.svg)"
  echo
  echo "The spatial metric: the largest step between neighbouring pixels of the ERROR image (the frame"
  echo "minus its exact reference, \`eval::mediaReference\`), where either shows media and the bare frame"
  echo "is flat, layer at full resolution, no lights or shimmer. The medium's own gradients are in both"
  echo "and cancel; a billboard cut by a wall is a step the reference does not have. On one dense smoke"
  echo "ball with a slanted wall through its centre (no detail video, 160 x 120) planar billboards show"
  echo "the cut, soft ones a little of it, spherical ones none. On explosion-walls the four methods come"
  echo "out the same: whatever sets that scene's largest step is shared by all of them, and the walls'"
  echo "cuts are smaller there. The tests assert the isolated case too (\`media_test\`'s slanted wall:"
  echo "planar jumps more than 0.3 between neighbours, spherical and soft less than 0.12)."
  echo
  echo "## Speed against accuracy"
  echo
  echo "### What \`--max-error\` measures (\`media-budget.md\`, quoted by docs/media.md)"
  echo
  tail -n +3 "$out/media-budget.md"
  echo
  echo "**What each point is.** One art scene drawn by one method with the media layer at one"
  echo "resolution (1/8, 1/4, 1/2 or 1 of the output; the label). x: the median wall time of a whole"
  echo "frame (\`SceneRenderer::renderFrame\`: opaque pass, resolve, media, compose, read-back) over"
  echo "three frames of the scene's camera path (first, middle, last). y: the worst over those frames"
  echo "of the RMSE, in scene-linear colour (not clamped), against the exact model reference"
  echo "(\`puff::reference\`: every particle's exact path through each pixel's ray, double precision,"
  echo "composited along the ray, over the same opaque layer; docs/measurement.md says what both sides"
  echo "leave out). The tables add, worst over the same frames, the RMSE over the media pixels and in"
  echo "the clip band, SSIM, and (with \`puffbench --physical\`) the RMSE against the physical reference. The dashed line is the Pareto front: the configurations nothing else beats on"
  echo "both. \`baseline_ms\` in the CSV is the same frame without media particles; \`floor_ms\` the"
  echo "fill-rate floor, measured in the same run at each layer resolution: the same frame with every"
  echo "media particle's quad drawn by a fragment program that computes nothing"
  echo "(\`SceneRenderer::setFillRateFloor\`), and \`ratio_to_floor\` divides by it."
  echo
  echo "How to read it: along one method's points the layer resolution trades time for error. Where a"
  echo "method's error stops falling as the layer gets finer, what is left is the method's own error"
  echo "(planar billboards cut by walls or popping at the near plane; soft ones fading where nothing"
  echo "fades) plus the floor every method shares: the float layers' rounding and the view-axis sort. Where the methods' points coincide, that scene's sampled frames do not show"
  echo "their differences."
  echo
  for scene in $(tail -n +2 "$out/media.csv" | cut -d, -f1 | sort -u); do
    echo "## $scene"
    echo
    echo "![$scene]($scene.svg)"
    echo
    echo "| method | resolution | frame ms | x no media | x fill-rate floor | worst RMSE | PSNR dB | media RMSE | band RMSE | SSIM | physical RMSE | Pareto |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    awk -F, -v scene="$scene" 'NR == 1 {for (i = 1; i <= NF; ++i) col[$i] = i; next}
        function v(name) {return (name in col) ? $col[name] : ""}
        function e(x) {return x == "" ? "" : sprintf(x + 0 >= 0.001 || x + 0 == 0 ? "%.4f" : "%.2g", x)}
        $1 == scene {printf "| %s | %s | %.1f | %.2f | %s | %.5f | %.1f | %s | %s | %s | %s | %s |\n", v("method"), v("resolution"),
          v("median_ms"), v("ratio_to_baseline"), v("ratio_to_floor"), v("worst_rmse"), v("psnr_db"), e(v("worst_rmse_media")),
          e(v("worst_rmse_band")), (v("worst_ssim") == "" ? "" : sprintf("%.4f", v("worst_ssim"))), e(v("worst_rmse_physical")),
          (v("pareto") == 1 ? "yes" : "")}' "$out/media.csv"
    echo
  done
} > "$out/README.md"
echo "report.sh: wrote $out/README.md, $out/media-budget.md, $out/paper-tables.md, $out/coverage.md, $out/hull-costs.md, $out/cel-bench.md, $out/tumble-table.md, docs/bench/media-tables.md and the charts${seconds:+ (benchmarks: $seconds s)}"
