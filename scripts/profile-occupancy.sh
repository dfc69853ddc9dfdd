#!/usr/bin/env bash
# Achieved occupancy, DRAM traffic and time per kernel in chosen step ranges of a scene (Levine
# et al.'s Table 2), read by Nsight Compute inside the NVTX ranges `perifrac profile` marks.
#   scripts/profile-occupancy.sh SCENE RANGES [SCALE] [KERNELS_PER_RANGE]
#   e.g. scripts/profile-occupancy.sh scenes/glass_plate_projectile.toml 0:1000,6000:7000,18000:19000
# Profiles the first KERNELS_PER_RANGE (default 200, ~20 steps) kernels of each range. Writes
# $OUT/profile-occupancy/<range>.csv and occupancy.md; needs a GPU, ncu and a CUDA build.
set -euo pipefail
cd "$(dirname "$0")/.."
export PATH="$PATH:/usr/local/cuda/bin"
scene=$1 ranges=$2 scale=${3:-1} count=${4:-200}
bin=${PERIFRAC_BIN:-build/cuda/perifrac}
out=${OUT:-out}/profile-occupancy
mkdir -p "$out"
command -v ncu >/dev/null || { echo "profile-occupancy: ncu (Nsight Compute) not found" >&2; exit 1; }

source scripts/ncu-metrics.sh
last=${ranges##*:}
# The run's own per-range table and timeline (unprofiled), and the bond count.
"$bin" profile "$scene" --scale "$scale" --backend cuda --ranges "$ranges" --out "$out" | tee "$out/profile.txt"
bonds=$(awk '/^profile/ {for (i = 1; i < NF; ++i) if ($(i + 1) == "bonds,") print $i}' "$out/profile.txt")
{
  echo "# Achieved occupancy per step range, $(basename "$scene") (scale $scale), $(nvidia-smi --query-gpu=name --format=csv,noheader | head -n 1), $(date -u +%Y-%m-%d)"
  IFS=, read -ra list <<<"$ranges"
  for r in "${list[@]}"; do
    a=${r%%:*} b=${r##*:}
    ncu --nvtx --nvtx-include "pd-range-$a-$b/" --launch-count "$count" --metrics "$metrics" --csv \
      --print-units base "$bin" profile "$scene" --scale "$scale" --backend cuda --ranges "$r" \
      --steps "$last" --out "$out/runs" >"$out/$a-$b.csv" 2>"$out/$a-$b.err"
    echo
    echo "## steps $a:$b (first $count kernels)"
    echo
    python3 scripts/profile_table.py "$out/$a-$b.csv" "$bonds"
  done
} | tee "$out/occupancy.md"
