#!/usr/bin/env bash
# Runs a command under a private Xvfb server: with_xvfb.sh COMMAND [ARGS...]
# The server picks its own free display (-displayfd), so tests that run at the same time never
# share or race for one, as `xvfb-run -a` can (it picks a number from lock files, then starts the
# server). The server goes when the command ends; the command's exit status is the script's.
set -euo pipefail
[ $# -ge 1 ] || { echo "usage: with_xvfb.sh COMMAND [ARGS...]" >&2; exit 2; }
command -v Xvfb >/dev/null || { echo "with_xvfb.sh: Xvfb not found (Debian: apt install xvfb)" >&2; exit 2; }
work=$(mktemp -d)
fifo=$work/display
mkfifo "$fifo"
Xvfb -displayfd 3 -screen 0 1280x1024x24 -nolisten tcp 3>"$fifo" 2>"$work/xvfb.log" &
xvfb=$!
trap 'kill "$xvfb" 2>/dev/null; wait "$xvfb" 2>/dev/null; rm -rf "$work"' EXIT
display=
read -r -t 30 display <"$fifo" || true
if [ -z "$display" ]; then
  echo "with_xvfb.sh: Xvfb did not start: $(tail -n 1 "$work/xvfb.log")" >&2
  exit 2
fi
status=0
DISPLAY=:$display "$@" || status=$?
exit "$status"
