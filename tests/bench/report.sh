#!/usr/bin/env bash
# Regenerates docs/report/ (issue 7: speed against accuracy): runs puffbench on the art scenes,
# keeps its CSV, draws error-against-time charts with gnuplot (PNG and SVG) and writes the page
# docs/report/README.md with what was run on what machine.
#   tests/bench/report.sh [BUILD_DIR (build)] [puffbench options, e.g. --reps 5 --size 640 480]
# Needs a build with PUFF_BUILD_BENCH=ON (the default) and gnuplot (Debian: gnuplot-nox).
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
shift || true
out=docs/report
command -v gnuplot >/dev/null || { echo "report.sh: error: gnuplot not found (apt-get install gnuplot-nox)" >&2; exit 1; }
[ -x "$build/tests/puffbench" ] || { echo "report.sh: error: $build/tests/puffbench not built (cmake --build $build --target puffbench)" >&2; exit 1; }
mkdir -p "$out"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

start=$(date +%s)
PUFF_GL=${PUFF_GL:-osmesa} "$build/tests/puffbench" --csv "$tmp/media.csv" "$@" 2> "$tmp/log.txt" || { cat "$tmp/log.txt" >&2; exit 1; }
seconds=$(( $(date +%s) - start ))
gl=$(sed -n '1s/^puffbench: //p' "$tmp/log.txt")
cpu=$(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)
cores=$(nproc)

# One chart per scene: worst RMSE (log) against median frame time, one series per method, each point
# labelled with its layer resolution; the Pareto front drawn through.
for scene in $(tail -n +2 "$tmp/media.csv" | cut -d, -f1 | sort -u); do
  grep "^$scene," "$tmp/media.csv" > "$tmp/$scene.dat"
  awk -F, '$11 == 1' "$tmp/$scene.dat" | sort -t, -k6,6g > "$tmp/$scene.front"
  for term in "pngcairo size 900,600 font ',11'" "svg size 900,600 font 'sans,11'"; do
    ext=$([[ $term == png* ]] && echo png || echo svg)
    gnuplot <<GP
set terminal $term
set output "$tmp/$scene.$ext"
set datafile separator ","
set title "$scene: error against the exact reference vs frame time (labels: media layer resolution)"
set xlabel "median frame time, ms (this machine)"
set ylabel "worst RMSE over 3 frames, linear colour"
set logscale y
set grid
set key top right
plot for [m in "planar soft-linear soft-scurve spherical"] "$tmp/$scene.dat" using (stringcolumn(2) eq m ? \$6 : 1/0):9 with points pt 7 ps 1.3 title m, \
     "$tmp/$scene.dat" using 6:9:(sprintf("%g", \$3)) with labels offset 1.2,0.6 font ",8" notitle, \
     "$tmp/$scene.front" using 6:9 with lines lw 1.5 dt 2 lc rgb "#555555" title "Pareto front"
GP
  done
done

cp "$tmp/media.csv" "$out/media.csv"
for f in "$tmp"/*.png "$tmp"/*.svg; do cp "$f" "$out/"; done

{
  echo "# Speed against accuracy: the media path"
  echo
  echo "Regenerate with \`tests/bench/report.sh${*:+ $build $*}\` (it rewrites this page, the charts and"
  echo "\`media.csv\`). Last run: $(date -u +%Y-%m-%d), $seconds s, on $cores cores of $cpu; GL: $gl."
  echo "Times are this machine's (a software rasterizer, not a GPU): compare them within one run."
  echo
  echo "**What each point is.** One art scene drawn by one method with the media layer at one"
  echo "resolution (1/8, 1/4, 1/2 or 1 of the output; the label). x: the median wall time of a whole"
  echo "frame (\`SceneRenderer::renderFrame\`: opaque pass, resolve, media, compose, read-back) over"
  echo "three frames of the scene's camera path (first, middle, last). y: the worst over those frames"
  echo "of the RMSE, in linear colour, against the exact reference (\`puff::reference\`: every"
  echo "particle's exact path through each pixel's ray, double precision, composited along the ray,"
  echo "over the same opaque layer; \`runtime/include/puff/render/budget.h\` says what both sides"
  echo "leave out). The dashed line is the Pareto front: the configurations nothing else beats on"
  echo "both. \`baseline_ms\` in the CSV is the same frame without media particles."
  echo
  echo "How to read it: along one method's points the layer resolution trades time for error. Where a"
  echo "method's error stops falling as the layer gets finer, what is left is the method's own error"
  echo "(planar billboards cut by walls or popping at the near plane; soft ones fading where nothing"
  echo "fades) plus the floor every method shares: the 8-bit output's rounding (about 0.0011) and the"
  echo "view-axis sort. Where the methods' points coincide, that scene's sampled frames do not show"
  echo "their differences. Only the media layer resolution and the method vary here; particle count"
  echo "and atlas or mesh detail are not swept yet (issue 7)."
  echo
  for scene in $(tail -n +2 "$out/media.csv" | cut -d, -f1 | sort -u); do
    echo "## $scene"
    echo
    echo "![$scene]($scene.svg)"
    echo
    echo "| method | resolution | frame ms | x baseline | worst RMSE | PSNR dB | Pareto |"
    echo "| --- | --- | --- | --- | --- | --- | --- |"
    grep "^$scene," "$out/media.csv" | awk -F, '{printf "| %s | %s | %.1f | %.2f | %.5f | %.1f | %s |\n", $2, $3, $6, $8, $9, $10, ($11 == 1 ? "yes" : "")}'
    echo
  done
} > "$out/README.md"
echo "report.sh: wrote $out/README.md, $out/media.csv and the charts ($seconds s)"
