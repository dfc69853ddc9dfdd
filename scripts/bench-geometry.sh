#!/usr/bin/env bash
# The geometry timing table of docs/geometry.md: grid, TetGen tet and Voronoi particles at about
# 600k on the procedural sphere and on spot.obj (skipped where absent), with 1 thread and with
# all cores, each stage timed by `perifrac bench-geometry`. A benchmark, not a test.
#   scripts/bench-geometry.sh                    build/cpu/perifrac, 600000 particles
#   PERIFRAC=build/x/perifrac COUNT=100000 scripts/bench-geometry.sh
#   MESHES=path/to/meshes scripts/bench-geometry.sh   where spot.obj lives (default ../shared/data/meshes)
# Writes bench/results/geometry-<UTC date>.csv and the logs next to it.
set -uo pipefail
cd "$(dirname "$0")/.."
perifrac=${PERIFRAC:-build/cpu/perifrac}
count=${COUNT:-600000}
meshes=${MESHES:-../shared/data/meshes}
out=bench/results
mkdir -p "$out"
csv="$out/geometry-$(date -u +%Y-%m-%d).csv"
log="$out/geometry-$(date -u +%Y-%m-%d).log"
[ -x "$perifrac" ] || { echo "bench-geometry: no $perifrac (build it, or set PERIFRAC)" >&2; exit 2; }

shapes=("--shape sphere")
if [ -f "$meshes/spot.obj" ]; then
  shapes+=("--shape mesh --mesh $meshes/spot.obj")
else
  echo "bench-geometry: $meshes/spot.obj not found, spot skipped"
fi
kinds="grid tets voronoi"
command -v tetgen >/dev/null || { echo "bench-geometry: no tetgen on PATH, tets skipped"; kinds="grid voronoi"; }
threads_list=${THREADS:-"1 $(nproc)"}
for shape in "${shapes[@]}"; do
  for kind in $kinds; do
    for threads in $threads_list; do
      # TetGen is one single-threaded program: one run is enough.
      [ "$kind" = tets ] && [ "$threads" != "$(echo "$threads_list" | awk '{print $NF}')" ] && continue
      # shellcheck disable=SC2086
      "$perifrac" bench-geometry $shape --particles "$kind" --count "$count" --threads "$threads" --csv "$csv" \
        | tee -a "$log"
    done
  done
done
echo "bench-geometry: rows in $csv, output in $log"
