#!/usr/bin/env bash
# The GPU benchmark, packed on the build machine and run where nothing is built (docs/bench/gpu.md).
#
#   bash tests/bench/gpu.sh pack [BUILD] [PACKAGE]
#       On the build machine: builds puff_gpubench and puff_cook_scene in BUILD (default build), cooks
#       the benchmark's scenes (no image library needed to read them) and copies the binary,
#       the shared libraries it needs and this script into PACKAGE (default BUILD/gpu-package; an
#       existing PACKAGE must be an earlier package, which is replaced). Fails if the binary needs
#       OpenImageIO, GLFW, OSMesa, X11 or Wayland.
#   bash tests/bench/gpu.sh check BINARY
#       Whether BINARY needs only what a GPU machine has: fails, naming them, on OpenImageIO, GLFW,
#       OSMesa, X11 or Wayland among the libraries it loads (pack runs it on puff_gpubench).
#   bash PACKAGE/gpu.sh run [puff_gpubench options...]   (or tests/bench/gpu.sh run: build/gpu-package)
#       On the target: runs the packed binary on the GPU through EGL with the packed libraries, and
#       writes the CSV (--csv FILE; default PACKAGE/gpubench.csv). Needs only bash and the GPU's
#       driver (its libEGL vendor library, found through libglvnd's vendor files or
#       __EGL_VENDOR_LIBRARY_DIRS / _FILENAMES); brings libglvnd's libEGL, and glibc for a target
#       whose own is older than the build machine's.
set -euo pipefail

script_dir=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
scenes=(cloud-50k dust-roll explosion-walls)
# What the binary must not need: the image library and the window systems a GPU machine may lack.
forbidden='libOpenImageIO|libglfw|libOSMesa|libX11|libwayland'
# glibc's own libraries: packed apart, used only where the target's glibc is older.
glibc_libs='^(ld-linux[^/]*|libc|libm|libpthread|libdl|librt|libresolv)\.so'

die() {
  echo "gpu.sh: error: $*" >&2
  exit 1
}

pack() {
  local build=${1:-build}
  local package=${2:-$build/gpu-package}
  local repo
  repo=$(cd "$script_dir/../.." && pwd)
  [ -f "$build/CMakeCache.txt" ] || die "$build: not a configured build (run setup.sh or cmake first)"
  cmake --build "$build" --target puff_gpubench puff_cook_scene -j"$(nproc)" >/dev/null ||
    die "building puff_gpubench and puff_cook_scene in $build failed"
  local art=${PUFF_ART:-$build/art}
  [ -f "$art/default/puff.json" ] || die "$art: no baked art (build the default target, which bakes it)"
  local bin=$build/tests/puff_gpubench
  [ -x "$bin" ] || die "$bin: not built (a build without EGL has no GPU benchmark)"

  # Only a package is replaced: a directory that holds anything else is refused, never emptied.
  if [ -e "$package" ] && { [ ! -d "$package" ] || [ -n "$(ls -A "$package")" ]; } &&
    ! { [ -x "$package/bin/puff_gpubench" ] && [ -f "$package/gpu.sh" ] && [ -f "$package/glibc-version" ]; }; then
    die "$package: exists and is not a GPU-benchmark package; name a new directory"
  fi
  local staging=$package.tmp-$$
  rm -rf "$staging"
  mkdir -p "$staging/bin" "$staging/lib/glibc" "$staging/scenes"
  trap 'rm -rf "$staging"' EXIT
  for s in "${scenes[@]}"; do
    "$build/tests/puff_cook_scene" "$repo/art/scenes/$s.json" -o "$staging/scenes/$s.json" --art-dir "$art" -q ||
      die "cooking art/scenes/$s.json failed"
  done
  cp "$bin" "$staging/bin/"
  cp "$script_dir/gpu.sh" "$staging/gpu.sh"

  check "$bin"
  local libs lib name
  libs=$(libraries "$bin")
  for lib in $libs; do
    name=$(basename "$lib")
    if [[ $name =~ $glibc_libs ]]; then cp -L "$lib" "$staging/lib/glibc/$name"; else cp -L "$lib" "$staging/lib/$name"; fi
  done
  getconf GNU_LIBC_VERSION | awk '{print $2}' >"$staging/glibc-version"
  rm -rf "$package"  # checked above: nothing there, or a package
  mv "$staging" "$package"
  trap - EXIT
  echo "gpu.sh: packed $package ($(du -sh "$package" | cut -f1)): $(find "$package/lib" -type f | wc -l) libraries," \
    "scenes ${scenes[*]}; on the target: bash $package/gpu.sh run"
}

# The shared libraries binary $1 loads, one path a line.
libraries() { ldd "$1" | awk '/=>/ && $3 ~ /^\// {print $3} !/=>/ && $1 ~ /^\// {print $1}'; }

check() {
  local bin=${1:?check needs a binary}
  [ -x "$bin" ] || die "$bin: not an executable"
  local bad
  bad=$(libraries "$bin" | grep -E "$forbidden" || true)
  [ -z "$bad" ] || die "$(basename "$bin") needs $(echo $bad | tr ' ' ','); the GPU benchmark must need EGL alone"
}

# Whether version $1 (as "2.36") is older than $2.
older() { [ "$1" != "$2" ] && [ "$(printf '%s\n%s\n' "$1" "$2" | sort -V | head -1)" = "$1" ]; }

run() {
  # The package this script was packed into, else the build's.
  local package=$script_dir
  [ -x "$package/bin/puff_gpubench" ] || package=$(cd "$script_dir/../.." && pwd)/build/gpu-package
  [ -x "$package/bin/puff_gpubench" ] || die "$package: not a packed benchmark (run: bash tests/bench/gpu.sh pack)"
  local args=("$@") has_csv=0 a
  for a in "${args[@]}"; do [ "$a" = "--csv" ] && has_csv=1; done
  [ $has_csv = 1 ] || args+=(--csv "$package/gpubench.csv")

  # libglvnd finds the driver's EGL through its vendor files; a driver installed without them (a
  # bare NVIDIA runtime) gets one written here.
  if [ -z "${__EGL_VENDOR_LIBRARY_DIRS:-}${__EGL_VENDOR_LIBRARY_FILENAMES:-}" ] &&
    ! compgen -G '/usr/share/glvnd/egl_vendor.d/*.json' >/dev/null && ! compgen -G '/etc/glvnd/egl_vendor.d/*.json' >/dev/null; then
    if ldconfig -p 2>/dev/null | grep -q 'libEGL_nvidia.so.0'; then
      mkdir -p "$package/egl_vendor.d"
      printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "libEGL_nvidia.so.0"}}\n' \
        >"$package/egl_vendor.d/10_nvidia.json"
      export __EGL_VENDOR_LIBRARY_DIRS=$package/egl_vendor.d
    else
      die "no EGL driver here: no vendor file in /usr/share/glvnd/egl_vendor.d and no libEGL_nvidia.so.0"
    fi
  fi
  command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L >&2 || true

  local host built
  host=$(getconf GNU_LIBC_VERSION 2>/dev/null | awk '{print $2}')
  built=$(cat "$package/glibc-version")
  export PUFF_GL=egl
  if [ -n "$host" ] && ! older "$host" "$built"; then
    LD_LIBRARY_PATH=$package/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH} \
      "$package/bin/puff_gpubench" --scenes "$package/scenes" "${args[@]}"
  else
    echo "gpu.sh: this machine's glibc (${host:-unknown}) is older than the build's ($built): running on the packed one" >&2
    local loader
    loader=$(ls "$package"/lib/glibc/ld-linux*.so* | head -1)
    "$loader" --library-path "$package/lib:$package/lib/glibc" "$package/bin/puff_gpubench" \
      --scenes "$package/scenes" "${args[@]}"
  fi
}

case ${1:-} in
  pack) shift; pack "$@" ;;
  check) shift; check "$@" ;;
  run) shift; run "$@" ;;
  *)
    sed -n '2,18p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
    [ "${1:-}" = "--help" ] || [ "${1:-}" = "-h" ] || exit 2
    ;;
esac
