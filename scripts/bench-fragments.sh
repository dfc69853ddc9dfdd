#!/usr/bin/env bash
# The fragments timing table of docs/fragments.md: per-frame components, fits, crack mesh and
# piece mesh costs at about 600k particles of grid cubes, tets and Voronoi cells (intact, cut into
# 216 blocks, shattered), each stage timed by `perifrac bench-fragments`. A benchmark, not a test.
#   scripts/bench-fragments.sh                      build/cpu/perifrac, 600000 particles, all cores
#   PERIFRAC=build/x/perifrac COUNT=100000 KINDS="grid voronoi" scripts/bench-fragments.sh
# Writes bench/results/fragments-<UTC date>.csv and the log next to it.
set -uo pipefail
cd "$(dirname "$0")/.."
perifrac=${PERIFRAC:-build/cpu/perifrac}
count=${COUNT:-600000}
kinds=${KINDS:-"grid tets voronoi"}
threads=${THREADS:-$(nproc)}
out=bench/results
mkdir -p "$out"
csv="$out/fragments-$(date -u +%Y-%m-%d).csv"
log="$out/fragments-$(date -u +%Y-%m-%d).log"
[ -x "$perifrac" ] || { echo "bench-fragments: no $perifrac (build it, or set PERIFRAC)" >&2; exit 2; }
for kind in $kinds; do
  "$perifrac" bench-fragments --particles "$kind" --count "$count" --threads "$threads" --csv "$csv" | tee -a "$log"
done
echo "bench-fragments: rows in $csv, output in $log"
