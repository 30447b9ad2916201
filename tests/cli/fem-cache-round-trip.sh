#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# fem-cache-round-trip.sh PROGRAM ARGS...: `PROGRAM organ-poke ARGS --fem-cache F` twice: the
# first solves the FEM and keeps its forces in F, the second reads them from F, and both write
# the same CSV.
set -u
program=$1
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$program" organ-poke "$@" --fem-cache "$work/fem.csv" >"$work/first.csv" 2>"$work/first.err" ||
  { echo "first run failed:"; cat "$work/first.err"; exit 1; }
grep -q "fem: the forces kept in" "$work/first.err" || { echo "first run kept nothing:"; cat "$work/first.err"; exit 1; }
"$program" organ-poke "$@" --fem-cache "$work/fem.csv" >"$work/second.csv" 2>"$work/second.err" ||
  { echo "second run failed:"; cat "$work/second.err"; exit 1; }
grep -q "fem: the forces from" "$work/second.err" || { echo "second run solved again:"; cat "$work/second.err"; exit 1; }
grep -q "nodes, .* quadratic tets" "$work/second.err" && { echo "second run solved the FEM"; exit 1; }
cmp -s "$work/first.csv" "$work/second.csv" || { echo "the CSVs differ:"; diff "$work/first.csv" "$work/second.csv"; exit 1; }
echo "ok: $(head -1 "$work/fem.csv")"
