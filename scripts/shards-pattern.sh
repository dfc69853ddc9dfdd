#!/usr/bin/env bash
# Shards along a run's own cracks (issue 31): runs SCENE once to its last frame with a checkpoint,
# then again with [[shards]] `pattern` = that run (its broken bonds the faces, its dust in cells of
# SIZE m, the rest holding HOLD times the limits), and prints both runs' last fragments.csv rows:
# pieces, mass in single-particle pieces and in free particles, heaviest piece, pieces of >= 8
# particles, bonds broken. Stills of both last frames (and, for the glass plate, face-on with
# damage colours) go to $OUT/shards-pattern/NAME/. A benchmark of the look, not a test.
#   scripts/shards-pattern.sh SCENE SIZE [BINARY]      e.g. glass_plate_projectile 0.01
#   HOLD=10 SCALE=1 FRAMES=N EXTRA="--eye 0.9,0.6,1.4 --look-at 0.1,0.05,0" (still camera)
#   DUST_HOLD="2 3": one second run per value (shards[0].dust_hold; folders p2-dhVALUE), after the
#   one without it; REUSE=1 keeps a first run already in the folder.
set -uo pipefail
cd "$(dirname "$0")/.."
scene=${1:?scene name (scenes/NAME.toml)} size=${2:?dust cell size [m]} bin=${3:-build/cuda/perifrac}
[[ -x $bin ]] || { echo "shards-pattern: no perifrac binary at '$bin'" >&2; exit 2; }
[[ -f scenes/$scene.toml ]] || { echo "shards-pattern: no scene scenes/$scene.toml" >&2; exit 2; }
frames=${FRAMES:-$(sed -n 's/^frames *= *\([0-9]*\).*/\1/p' "scenes/$scene.toml" | head -n 1)}
dir=${OUT:-out}/shards-pattern/$scene
mkdir -p "$dir"
common=(--overwrite --scale "${SCALE:-1}" --frames "$frames" --set output.vtk=false)
if [[ ${REUSE:-0} != 1 || ! -f $dir/p1/checkpoint.pck ]]; then
  "$bin" run "scenes/$scene.toml" "${common[@]}" --checkpoint-every "$frames" --out "$dir/p1" >"$dir/p1.log" 2>&1 ||
    { echo "shards-pattern: the first run failed: $(tail -n 1 "$dir/p1.log")" >&2; exit 1; }
fi
second=(p2)
for dh in ${DUST_HOLD:-}; do second+=("p2-dh$dh"); done
for p in "${second[@]}"; do
  dust=()
  [[ $p == p2-dh* ]] && dust=(--set "shards[0].dust_hold=${p#p2-dh}")
  "$bin" run "scenes/$scene.toml" "${common[@]}" --set "shards[0].size=$size" --set "shards[0].hold=${HOLD:-10}" \
    "${dust[@]}" --set "shards[0].pattern=\"$(cd "$dir/p1" && pwd)\"" --out "$dir/$p" >"$dir/$p.log" 2>&1 ||
    { echo "shards-pattern: the second run $p failed: $(tail -n 1 "$dir/$p.log")" >&2; exit 1; }
done
last=$(printf %05d "$frames")
read -ra camera <<<"${EXTRA:-}"
for p in p1 "${second[@]}"; do
  grep -h '^shards' "$dir/$p.log"
  awk -F, -v p="$p" -v b="$(grep -o 'broken [0-9.]*%' "$dir/$p.log" | tail -n 1)" '{
    big = 0; for (i = 12; i <= 32; ++i) big += $i
    printf "%s  pieces %d  singles %.2f%%  free %.2f%%  heaviest %.1f%%  pieces>=8 %d  %s\n", p, $4, 100 * $6, 100 * $33,
      100 * $7, big, b }' <<<"$(tail -n 1 "$dir/$p/fragments.csv")"
  "$bin" render "$dir/$p" --frames "$frames" --width 960 --height 540 --spp 4 "${camera[@]}" --out "$dir/$p.still" \
    >/dev/null 2>&1 && cp "$dir/$p.still/frame_$last.png" "$dir/$p-still.png"
  [[ $scene == glass_plate_projectile ]] &&
    "$bin" render "$dir/$p" --frames "$frames" --width 540 --height 540 --spp 4 --eye 0,0,0.55 --look-at 0,0,0 \
      --material opaque --damage-colors --out "$dir/$p.face" >/dev/null 2>&1 &&
    cp "$dir/$p.face/frame_$last.png" "$dir/$p-face.png"
done
