#!/bin/sh
# A scene pays only for what it names (docs/features_cost.md): runs tools/bench/features_cost.lua
# (the base case with each unused feature declared, and with every diagnostic
# attached) and tools/bench/specialised_linear.cpp (the engine against a loop
# written for the linear base case), printing both tables.
#   tools/bench/features_cost.sh [build-dir] [steps]
# Timings are noisy on a shared machine: compare ratios from one run only.
set -e
here=$(cd "$(dirname "$0")" && pwd)
build=${1:-$here/../../build}
steps=${2:-20000}
cmake --build "$build" --target granule specialised_linear > /dev/null
echo "== features_cost.lua (linear) =="
"$build/granule" run "$here/features_cost.lua" --quiet -D steps="$steps" -D model=linear -D csv=features_cost_linear.csv
echo
echo "== features_cost.lua (walton_braun) =="
"$build/granule" run "$here/features_cost.lua" --quiet -D steps="$steps" -D model=walton_braun \
  -D only=plain,adhesive_pair_unused,gravity_zero,diagnostics_all,friction_off -D csv=features_cost_wb.csv
echo
echo "== specialised_linear =="
"$build/specialised_linear" "$steps" 3 60000
