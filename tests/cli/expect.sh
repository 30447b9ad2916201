#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# expect.sh PROGRAM ok|fail|fail-after-progress REGEX ARGS...
#   ok:   PROGRAM ARGS exits 0 and its stdout+stderr match REGEX (extended grep).
#   fail: it exits non-zero, prints exactly one line on stderr, and that line matches REGEX.
#   fail-after-progress: it exits non-zero and the last line on stderr, after the progress lines
#         of a long command, is its error and matches REGEX.
set -u
program=$1 expectation=$2 pattern=$3
shift 3
out=$(mktemp) err=$(mktemp)
trap 'rm -f "$out" "$err"' EXIT
"$program" "$@" >"$out" 2>"$err"
status=$?
if [ "$expectation" = ok ]; then
  if [ $status -ne 0 ]; then echo "expected exit 0, got $status"; cat "$err"; exit 1; fi
  if ! cat "$out" "$err" | grep -Eq -- "$pattern"; then
    echo "output does not match /$pattern/:"; head -20 "$out" "$err"; exit 1
  fi
elif [ "$expectation" = fail-after-progress ]; then
  if [ $status -eq 0 ]; then echo "expected a non-zero exit, got 0"; exit 1; fi
  last=$(tail -n 1 "$err")
  case $last in "tissuesim: error: "*) ;; *) echo "the last line on stderr is no error:"; cat "$err"; exit 1 ;; esac
  if ! printf '%s\n' "$last" | grep -Fq -- "$pattern"; then
    echo "the error does not contain '$pattern':"; cat "$err"; exit 1
  fi
  echo "ok: $(printf '%s' "$last" | head -c 200)"
  exit 0
else
  if [ $status -eq 0 ]; then echo "expected a non-zero exit, got 0"; exit 1; fi
  lines=$(grep -c '' "$err")
  if [ "$lines" -ne 1 ]; then echo "expected one line on stderr, got $lines:"; cat "$err"; exit 1; fi
  if ! grep -Fq -- "$pattern" "$err"; then echo "stderr does not contain '$pattern':"; cat "$err"; exit 1; fi
fi
echo "ok: $(head -c 200 "$err" | head -1)"
