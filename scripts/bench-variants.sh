#!/usr/bin/env bash
# Builds the CUDA preset once per variant of compile flags and times the lattice benchmarks
# of each, for speed work (bench/NOTES.md). Usage, on a GPU machine:
#   scripts/bench-variants.sh "NAME=CUDA_FLAGS" ...     e.g. "unroll1=-DPERIFRAC_BOND_UNROLL=1"
# Prints one line per variant and model: springforces and full-step bond-updates/s.
set -uo pipefail
cd "$(dirname "$0")/.."
export PATH="$PATH:/usr/local/cuda/bin"
OUT=${OUT:-out}/variants
mkdir -p "$OUT"
models=${MODELS:-bond_based state_based plastic}
for spec in "$@"; do
  name=${spec%%=*} flags=${spec#*=}
  dir=build/variant-$name
  cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPERIFRAC_TESTS=OFF -DCMAKE_CUDA_ARCHITECTURES=90 \
    -DCMAKE_CUDA_FLAGS="$flags" >/dev/null && cmake --build "$dir" -j "$(nproc)" >"$OUT/build-$name.log" 2>&1 ||
    { echo "$name: build failed (see $OUT/build-$name.log)"; continue; }
  for model in $models; do
    "$dir/perifrac" bench --lattice 100 --model "$model" --backend cuda --steps 300 --warmup 30 \
      --out "$OUT/results-$name" >"$OUT/$name-$model.log" 2>&1
    spring=$(awk '/^pd\/springforces \(all\)/ {print $6}' "$OUT/$name-$model.log")
    step=$(awk '/^step \(all kernels\)/ {print $7}' "$OUT/$name-$model.log")
    printf '%-14s %-12s springforces %-28s step %s\n' "$name" "$model" "$spring" "$step"
  done
done
