#!/usr/bin/env bash
# The demo: sets up, then throws a steel ball through a window of breakaway glass
# (scenes/demo_window.toml) on the best backend here, rendering the frames as the run goes (the
# scene's [render] block: a glass pane, the ball drawn) and a movie where ffmpeg is present. On a
# GPU the full 0.61M-particle pane; on the CPU-reference backend an 11k-particle preview of the
# same 24 ms (a longer step for the coarser particles: 0.77 of their stable step), about a minute
# on 2 cores.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/setup.sh
preset=$(cat build/.last-preset)
bin="build/$preset/perifrac"
out=out/demo
if [ "$preset" = cuda ]; then
  "$bin" run --overwrite scenes/demo_window.toml --backend cuda --out "$out"
else
  "$bin" run --overwrite scenes/demo_window.toml --backend cpu --scale 0.02 \
    --set simulation.dt=1.6e-6 --set simulation.steps_per_frame=625 --frames 24 --out "$out"
fi
echo "demo: frames in $out (particles: *.vtu for ParaView, *.pfr), images and movie in $out/render/"
