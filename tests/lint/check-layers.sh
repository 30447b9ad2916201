#!/bin/bash
# SPDX-License-Identifier: Apache-2.0
# The build enforces core's layering (core/CMakeLists.txt): the probe, compiled with the springs
# layer's include folders, finds its own layer's header and not the sim layer's.
# Usage: check-layers.sh BUILD_DIR
set -u
output=$(cmake --build "$1" --target tissuesim_layer_probe 2>&1)
status=$?
if [ $status -eq 0 ]; then
  echo "check-layers: the springs layer compiled an include of sim/Simulation.h" >&2
  exit 1
fi
if ! grep -q "sim/Simulation.h: No such file" <<<"$output"; then
  echo "check-layers: the probe failed for another reason:" >&2
  echo "$output" | tail -20 >&2
  exit 1
fi
if grep -q "springs/SpringMesh.h: No such file" <<<"$output"; then
  echo "check-layers: the springs layer does not see its own header" >&2
  exit 1
fi
echo "check-layers: a layer sees its own headers and not those of the layers above it"
