#!/bin/sh
# SPDX-License-Identifier: Apache-2.0
# Makes the FEM reference's conformal tet mesh of the bundled liver (liver-fem.geo) with Gmsh
# (Debian's gmsh package): ./make-liver-fem.sh OUTPUT.msh [GMSH OPTIONS], e.g.
#   ./make-liver-fem.sh liver-fem.msh
#   ./make-liver-fem.sh liver-fem-fine.msh -setnumber finest 0.0005
#   ./make-liver-fem.sh graded.msh -setnumber finest 0.001 -setnumber growth 0.1 -setnumber coarsest 0.006
set -eu
here=$(cd "$(dirname "$0")" && pwd)
output=$1
shift
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The drawn surface in metres (the scenes' 0.03 m per unit), as ASCII STL.
awk 'BEGIN { print "solid liver" }
     $1 == "v" { n++; x[n] = $2 * 0.03; y[n] = $3 * 0.03; z[n] = $4 * 0.03 }
     $1 == "f" {
       for (k = 2; k <= NF; k++) { split($k, part, "/"); corner[k - 1] = part[1] }
       for (k = 2; k < NF - 1; k++) {
         print "facet normal 0 0 0"; print " outer loop"
         split(corner[1] " " corner[k] " " corner[k + 1], tri, " ")
         for (c = 1; c <= 3; c++) printf "  vertex %.9g %.9g %.9g\n", x[tri[c]], y[tri[c]], z[tri[c]]
         print " endloop"; print "endfacet"
       }
     }
     END { print "endsolid liver" }' "$here/liver-smooth.obj" > "$work/liver-smooth-m.stl"
cp "$here/liver-fem.geo" "$work/"
case $output in /*) ;; *) output=$(pwd)/$output ;; esac
(cd "$work" && gmsh -3 liver-fem.geo -o "$output" "$@" > gmsh.log 2>&1) || { cat "$work/gmsh.log"; exit 1; }
grep -q "^Error" "$work/gmsh.log" && { grep "^Error" "$work/gmsh.log"; exit 1; }
echo "wrote $output"
