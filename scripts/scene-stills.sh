#!/usr/bin/env bash
# Runs a scene and renders chosen frames to PNG.
#   scripts/scene-stills.sh SCENE OUT "FRAME FRAME ..." [perifrac run options...]
# Frames are written to OUT/ as usual; the chosen frames' images go to OUT/stills/.
set -euo pipefail
cd "$(dirname "$0")/.."
scene=$1 out=$2 frames=$3
shift 3
preset=$(cat build/.last-preset 2>/dev/null || echo cpu)
bin=${PERIFRAC_BIN:-build/$preset/perifrac}
"$bin" run "$scene" --out "$out" "$@"
# Render only the chosen frames: link them into a folder of their own.
mkdir -p "$out/chosen"
ln -sf "../rest.pfr" "$out/chosen/rest.pfr"
for f in $frames; do
  name=$(printf 'frame_%05d.pfr' "$f")
  ln -sf "../$name" "$out/chosen/$name"
done
"$bin" render "$out/chosen" --out "$out/stills" ${RENDER_OPTIONS:-}
