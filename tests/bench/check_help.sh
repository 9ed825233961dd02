#!/usr/bin/env bash
# Every benchmark given: `--help` prints its usage on stdout and exits 0 (nothing on stderr, no GL
# context made); an unknown flag prints it on stderr and exits 2.
# Usage: check_help.sh BENCHMARK...
set -uo pipefail
status=0
for exe in "$@"; do
  name=$(basename "$exe")
  out=$("$exe" --help 2>/tmp/check_help_err.$$)
  rc=$?
  if [ $rc -ne 0 ] || [[ $out != usage:\ $name* ]] || [ -s /tmp/check_help_err.$$ ]; then
    echo "check_help: $name --help: exit $rc, stdout: ${out:0:80}" >&2
    status=1
  fi
  out=$("$exe" --no-such-flag 2>/dev/null)
  rc=$?
  if [ $rc -ne 2 ] || [ -n "$out" ]; then
    echo "check_help: $name --no-such-flag: exit $rc (want 2), stdout: ${out:0:80}" >&2
    status=1
  fi
done
rm -f /tmp/check_help_err.$$
exit $status
