#!/usr/bin/env bash
# Kernel profile with Nsight Compute (ncu), after Levine et al.'s Table 2: per kernel, the time,
# DRAM traffic and bandwidth, bytes per bond update, registers and achieved occupancy, for the
# bench lattice of each material model. Needs a GPU, ncu and a CUDA build.
#   scripts/profile.sh [BINARY] [LATTICE]      (default build/cuda/perifrac, 100 per side)
#   PROFILE_WARMUP=300 scripts/profile.sh      only the 2 steps after 300 warm-up steps (the bench's
#                                              timed range), e.g. the plastic lattice once few yield
# Writes $OUT/profile/<model>.csv (raw ncu) and profile.md (the tables); prints the tables.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$PATH:/usr/local/cuda/bin"
bin=${1:-build/cuda/perifrac}
lattice=${2:-100}
warmup=${PROFILE_WARMUP:-1}
# Every kernel of the run (set-up included) after one warm-up step; only the timed steps after more.
select=(--launch-skip 0)
[ "$warmup" -gt 1 ] && select=(--nvtx --nvtx-include "pd-bench-timed/")
out=${OUT:-out}/profile
mkdir -p "$out"
command -v ncu >/dev/null || { echo "profile: ncu (Nsight Compute) not found" >&2; exit 1; }

source scripts/ncu-metrics.sh

device=$(nvidia-smi --query-gpu=name --format=csv,noheader | head -n 1)
{
  echo "# Kernel profile (ncu), $device, $(date -u +%Y-%m-%d), git ${PERIFRAC_GIT_REV:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)}"
  echo
  echo "Lattice of ${lattice}^3 particles, delta = 3 lambda, float32; 2 profiled steps after $warmup warm-up step(s)."
  for model in bond_based state_based plastic; do
    # The bond count for bytes per bond update, from an unprofiled run.
    bonds=$("$bin" bench --lattice "$lattice" --model "$model" --backend cuda --steps 1 --warmup 0 \
              --out "$out/bench" | awk '/^size/ {print $4; exit}')
    ncu --metrics "$metrics" --csv --print-units base "${select[@]}" \
      "$bin" bench --lattice "$lattice" --model "$model" --backend cuda --steps 2 --warmup "$warmup" \
      --out "$out/bench" >"$out/$model.csv" 2>"$out/$model.err"
    echo
    echo "## $model ($bonds bonds)"
    echo
    python3 scripts/profile_table.py "$out/$model.csv" "$bonds"
  done
} | tee "$out/profile.md"
