#!/usr/bin/env bash
# The demo: sets up, then runs the glass-plate scene on the best backend here (the full
# 131k-particle plate on a GPU; a small plate on the CPU-reference backend) and renders the
# frames to PNG.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
preset=$(cat build/.last-preset)
bin="build/$preset/perifrac"
scene=scenes/glass_plate_projectile.toml
out=out/demo
if [ "$preset" = cuda ]; then
  "$bin" run --overwrite "$scene" --backend cuda --out "$out"
else
  "$bin" run --overwrite "$scene" --backend cpu --scale 0.05 --frames 16 --out "$out"
fi
"$bin" render "$out"
echo "demo: frames in $out (particles: *.vtu for ParaView, *.pfr), images in $out/render/"
