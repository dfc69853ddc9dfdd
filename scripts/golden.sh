#!/usr/bin/env bash
# Golden outputs: runs six small scenes (bond-based, state-based plastic, anisotropic, tets falling
# and tets breaking on the floor, Voronoi; with contact, pre-cracks, anchors and projectiles among
# them) on one backend, renders their last frame, and prints the SHA-256 of every output file
# whose bytes are meant to depend only on the physics (files that record wall times, dates or
# paths are left out).
#   scripts/golden.sh [cpu|cuda] [BINARY] > sums.txt
# A change that must not move results is checked by running this before and after it with the
# same compiler and comparing the two lists (`diff`); bench/golden/ keeps lists so made.
# GOLDEN_LAUNCH (e.g. "mpirun -np 3") starts the runs through a launcher, GOLDEN_RUN_ARGS adds
# options to every run (scripts/mpi-equivalence.sh compares ranks this way).
set -euo pipefail
cd "$(dirname "$0")/.."
# The tetgen program staged by scripts/stage-deps.sh, on a machine without the package.
[[ -d .deps/bin ]] && export PATH="$PWD/.deps/bin:$PATH" LD_LIBRARY_PATH="$PWD/.deps/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
backend=${1:-cpu}
bin=${2:-build/$backend/perifrac}
out=${GOLDEN_OUT:-out/golden-$backend}
rm -rf "$out"
mkdir -p "$out"

# name scene scale frames steps_per_frame [run options]. vase_impact starts the vase 0.8 mm lower, so
# that it hits the floor and breaks within its frames: tets with listed families, surface factors,
# the screened and breaking force passes and floor contact (the vase's GPU run moved from its impact
# on under a change that left every other case's bits alone, bench/NOTES.md 2026-12-01).
cases=(
  "glass_plate scenes/glass_plate_projectile.toml 0.02 3 40"
  "plastic_wall scenes/chen_elastic_vs_plastic_wall.toml 0.02 2 40"
  "four_walls scenes/chen_four_walls.toml 0.005 2 40"
  "vase_tets scenes/vase_drop.toml 0.1 2 40"
  "vase_impact scenes/vase_drop.toml 0.1 3 60 --set bodies[0].center=[0.0,-0.0108,0.0]"
  "torus_voronoi scenes/torus_voronoi_drop.toml 0.05 2 40"
)
for c in "${cases[@]}"; do
  read -r name scene scale frames spf options <<<"$c"
  # shellcheck disable=SC2086  # (the case's options and GOLDEN_RUN_ARGS are words)
  ${GOLDEN_LAUNCH:-} "$bin" run --overwrite "$scene" ${options:-} ${GOLDEN_RUN_ARGS:-} --backend "$backend" --scale "$scale" --frames "$frames" --steps-per-frame "$spf" \
    --out "$out/$name" >"$out/$name.log" 2>&1 || { echo "golden: $name failed, see $out/$name.log" >&2; exit 1; }
  "$bin" render "$out/$name" --backend "$backend" --width 96 --height 64 --spp 1 >>"$out/$name.log" 2>&1 ||
    { echo "golden: rendering $name failed, see $out/$name.log" >&2; exit 1; }
done
# Run records (wall times, dates, the command line; the folder's lock, manifest and journal) and logs
# are not results.
(cd "$out" && find . -type f ! -name '*.log' ! -name 'run.*' ! -name '*.json' ! -name 'kernels*' \
  ! -name 'checkpoint*' | LC_ALL=C sort | xargs sha256sum)
