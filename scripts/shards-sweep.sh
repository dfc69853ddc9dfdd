#!/usr/bin/env bash
# Shards, not grit (issue 31): the gallery's breaking scenes at their full size, each with a sweep of
# the material's damage_alpha (the strain limit times 1 + alpha * damage), or with KNOB=shards of
# [[shards]] cells (SIZE:HOLD pairs, "none" for the scene as it is), and what the breakage
# leaves at the last frame: the share of the mass in single particles (dust) and of it in free
# particles (no bond left; "-" where the run's log has no such column), the heaviest piece's
# share, the pieces in all and those of at least 8 particles, and the broken bonds. A still of the
# last frame per run (damage colours: the crack pattern) goes to $OUT/shards-sweep/stills.
# A benchmark of the look, not a test; on a GPU (or a patient CPU).
#   scripts/shards-sweep.sh [BINARY] [SCENES]     SCENES: glass_plate vase elastic_drop (default all)
#   SCALE=0.1 FRAMES=3 scripts/shards-sweep.sh build/cpu/perifrac elastic_drop   (a quick look)
#   KNOB=shards SWEEP_glass_plate="none 0.01:10" scripts/shards-sweep.sh   (cells of 1 cm, hold 10)
#   KNOB=shards SWEEP_glass_plate="0.01:10:0.05" ...   (cells only within 5 cm of the impact point)
# The glass plate also gets a face-on still with damage colours (its crack pattern). Each run's
# singles are counted by rest distance from the scene's impact point (scripts/singles-where.py,
# $OUT/shards-sweep/NAME.where.txt) where python3 is present.
# Prints a table; writes $OUT/shards-sweep/table.txt.
set -uo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/cuda/perifrac}
only=${2:-"glass_plate vase elastic_drop"}
size=(--scale "${SCALE:-1}")
[[ -n ${FRAMES:-} ]] && size+=(--frames "$FRAMES")
OUT=${OUT:-out}/shards-sweep
mkdir -p "$OUT/stills"
[[ -x $bin ]] || { echo "shards-sweep: no perifrac binary at '$bin'" >&2; exit 2; }

# name | scene | material | alphas (the first is the scene's own) | impact point (a zone's centre);
# SWEEP_<name> replaces a list (e.g. SWEEP_vase="1 1.5 2")
knob=${KNOB:-alpha}
[[ $knob == alpha || $knob == shards ]] || { echo "shards-sweep: KNOB must be alpha or shards" >&2; exit 2; }
if [[ $knob == alpha ]]; then
  SWEEPS=(
    "glass_plate|glass_plate_projectile|glass|${SWEEP_glass_plate:-0 2 5 10}|0,0,0"
    "vase|vase_drop|clay|${SWEEP_vase:-0 3 6}|0,-0.16,0"
    "elastic_drop|chen_elastic_drop|jelly|${SWEEP_elastic_drop:-0.5 2 5}|0,-0.1,0"
  )
else
  SWEEPS=(
    "glass_plate|glass_plate_projectile|glass|${SWEEP_glass_plate:-none 0.01:10 0.02:10}|0,0,0"
    "vase|vase_drop|clay|${SWEEP_vase:-none 0.02:10 0.03:10}|0,-0.16,0"
    "elastic_drop|chen_elastic_drop|jelly|${SWEEP_elastic_drop:-none 0.03:10 0.05:10}|0,-0.1,0"
  )
fi
# The setting of one sweep value: MATERIAL VALUE IMPACT_POINT.
knob_args() {
  if [[ $knob == alpha ]]; then
    echo "--set materials.$1.damage_alpha=$2"
  elif [[ $2 != none ]]; then
    local size hold radius
    IFS=: read -r size hold radius <<<"$2"
    echo "--set shards[0].size=$size --set shards[0].hold=$hold"
    [[ -n $radius ]] && echo "--set shards[0].radius=$radius --set shards[0].center=[$3]"
  fi
}
rows=()
for sweep in "${SWEEPS[@]}"; do
  IFS='|' read -r name scene material alphas impact <<<"$sweep"
  [[ " $only " == *" $name "* ]] || continue
  for alpha in $alphas; do
    tag=${alpha/:/h}
    dir="$OUT/$name-${knob:0:1}${tag/:/r}"
    t0=$SECONDS
    # shellcheck disable=SC2046  # the settings split into their words
    if ! "$bin" run --overwrite "scenes/$scene.toml" $(knob_args "$material" "$alpha" "$impact") \
      "${size[@]}" --out "$dir" >"$dir.log" 2>&1; then
      rows+=("$(printf '%-13s %6s  run failed: %s' "$name" "$alpha" "$(tail -n 1 "$dir.log")")")
      continue
    fi
    secs=$((SECONDS - t0))
    # fragments.csv: frame,step,time,fragments,singles,single_mass_share,largest_mass_share,
    # largest_particles, then pieces per size bin 1, 2-3, 4-7, 8-15, ... (24 bins), free_mass_share
    last=$(tail -n 1 "$dir/fragments.csv")
    broken=$(grep -o 'broken [0-9.]*%' "$dir.log" | tail -n 1)
    rows+=("$(awk -F, -v n="$name" -v a="$alpha" -v s="$secs" -v b="${broken#broken }" '{
      big = 0; for (i = 12; i <= 32; ++i) big += $i
      free = NF >= 33 && $33 != "" ? sprintf("%.1f%%", 100 * $33) : "-"
      printf "%-13s %6s %6d %9.1f%% %9s %9.1f%% %8d %8d %8s %6ds", n, a, $1, 100 * $6, free, 100 * $7, $4, big, b, s }' <<<"$last")")
    frame=$(cut -d, -f1 <<<"$last")
    command -v python3 >/dev/null &&
      python3 scripts/singles-where.py "$dir" --center "$impact" --band 0.02 --bands 12 >"$OUT/$(basename "$dir").where.txt"
    "$bin" render "$dir" --frames "$frame" --width 960 --height 540 --spp 4 --out "$dir/still" >"$dir.render.log" 2>&1 &&
      cp "$dir/still/frame_$(printf %05d "$frame").png" "$OUT/stills/$(basename "$dir").png"
    [[ $name == glass_plate ]] &&
      "$bin" render "$dir" --frames "$frame" --width 540 --height 540 --spp 4 --eye 0,0,0.55 --look-at 0,0,0 \
        --material opaque --damage-colors --out "$dir/face" >>"$dir.render.log" 2>&1 &&
      cp "$dir/face/frame_$(printf %05d "$frame").png" "$OUT/stills/$(basename "$dir")-face.png"
  done
done
{
  echo "shards-sweep: $("$bin" --version 2>/dev/null | head -n 1), $(date -u +%Y-%m-%d), scale ${SCALE:-1}"
  nvidia-smi --query-gpu=name --format=csv,noheader 2>/dev/null | head -n 1
  printf '%-13s %6s %6s %10s %9s %10s %8s %8s %8s %7s\n' scene "$knob" frame singles free largest pieces "pieces>=8" broken run
  printf '%s\n' "${rows[@]}"
} | tee "$OUT/table.txt"
