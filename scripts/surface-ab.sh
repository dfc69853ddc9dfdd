#!/usr/bin/env bash
# The state-based surface correction on the gallery's state-based scenes: each scene run twice,
# as shipped (the correction off, the default) and with `surface_correction = true` on every
# state-based material, at full size on the GPU (or the CPU preview scale with --backend cpu).
# Prints one row per run: the bonds broken, the energy balance and the fragments of the last
# frame (count, mass in single particles, heaviest piece), the time per step; renders the still
# of each and puts the stills side by side in OUT/stills.tar. The default decision of issue 29
# reads these rows and stills (docs/validation.md).
#
#   scripts/surface-ab.sh BIN [--backend cuda|cpu] [--out DIR] [--only "NAME ..."]
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${1:?usage: scripts/surface-ab.sh BIN [--backend cuda|cpu] [--out DIR] [--only "NAME ..."]}
shift
BACKEND=cuda OUT=out/surface-ab ONLY=""
while [[ $# -gt 0 ]]; do
  case $1 in
    --backend) BACKEND=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --only) ONLY=$2; shift 2 ;;
    *) echo "error: unknown option '$1'" >&2; exit 2 ;;
  esac
done
mkdir -p "$OUT"

# name | scene | GPU scale | CPU scale | frames | still frame | camera (perifrac render options)
ENTRIES=(
  "four_walls|chen_four_walls|1|0.05|60|60|--eye 0.35,0.25,-0.75 --look-at 0,-0.03,-0.02"
  "elastic_vs_plastic|chen_elastic_vs_plastic_wall|1|0.1|60|60|"
  "glass_alpha_0|chen_glass_wall_alpha|1|0.05|60|60|--eye 0.12,0.12,-0.35 --look-at 0,0,-0.01"
  "ductile_gamma_0.1|chen_ductile_gamma|1|0.05|60|40|--eye 0.12,0.12,-0.35 --look-at 0,0,-0.01"
  "beams_bend|chen_beams_bend|1|0.2|60|20|"
  "bar_twist|chen_bar_twist|1|0.3|36|36|"
  "elastic_drop|chen_elastic_drop|1|0.1|60|60|--eye 0.9,0.6,1.4 --look-at 0.1,0.05,0"
  "thin_sheet|chen_thin_sheet_tear|1|0.1|60|50|"
  "jello|chen_jello_bullet|1|0.1|60|40|"
  "beams_poisson|chen_beams_poisson|1|0.3|150|150|"
  "bar_swing|chen_bar_swing|1|0.3|60|20|"
  "stretch_tear|chen_stretch_tear|1|0.1|60|50|"
  "glass_pressed|chen_glass_wall_pressed|1|0.05|50|50|"
)

# The --set options that turn the correction on for every isotropic state-based material of a
# scene (anisotropic ones cannot have it).
correction_sets() {
  awk '/^\[/ { name = "" } /^\[materials\.[A-Za-z0-9_]+\]/ { name = $1; gsub(/^\[materials\.|\]$/, "", name); order[++n] = name }
       /^model *= *"state_based"/ && name != "" { state[name] = 1 }
       /^\[materials\.[A-Za-z0-9_]+\.anisotropy\]/ { a = $1; gsub(/^\[materials\.|\.anisotropy\]$/, "", a); aniso[a] = 1 }
       END { for (k = 1; k <= n; ++k) if (state[order[k]] && !aniso[order[k]])
               printf "--set materials.%s.surface_correction=true ", order[k] }' "$1"
}

printf '%-18s %-4s %9s %9s %10s %8s %8s %8s\n' scene corr broken balance fragments singles largest "ms/step"
for entry in "${ENTRIES[@]}"; do
  IFS='|' read -r name scene gpu_scale cpu_scale frames still camera <<<"$entry"
  [[ -z $ONLY || " $ONLY " == *" $name "* ]] || continue
  scale=$gpu_scale
  [[ $BACKEND == cpu ]] && scale=$cpu_scale
  read -ra cam <<<"${camera:-}"
  for corr in off on; do
    sets=()
    [[ $corr == on ]] && read -ra sets <<<"$(correction_sets "scenes/$scene.toml")"
    dir=$OUT/$name-$corr
    if ! "$BIN" run --overwrite "scenes/$scene.toml" --backend "$BACKEND" --scale "$scale" --frames "$frames" \
      --out "$dir" --set output.vtk=false "${sets[@]}" >"$dir.log" 2>&1; then
      printf '%-18s %-4s failed: %s\n' "$name" "$corr" "$(grep -m1 -i error "$dir.log" || tail -n 1 "$dir.log")"
      continue
    fi
    last=$(grep -E '^frame [0-9]+/' "$dir.log" | tail -n 1)
    broken=$(sed -n 's/.* broken \([0-9.]*%\).*/\1/p' <<<"$last")
    balance=$(sed -n 's/.* energy balance \([-+0-9.]*%\).*/\1/p' <<<"$last")
    IFS=, read -r _ _ _ pieces _ single_share largest _ < <(tail -n 1 "$dir/fragments.csv")
    step_ms=$(sed -n 's/^step (all kernels) *[0-9]* *\([0-9.]*\) .*/\1/p' "$dir.log")
    printf '%-18s %-4s %9s %9s %10s %7.1f%% %7.1f%% %8s\n' "$name" "$corr" "$broken" "$balance" "$pieces" \
      "$(awk -v x="$single_share" 'BEGIN { print 100 * x }')" "$(awk -v x="$largest" 'BEGIN { print 100 * x }')" \
      "$step_ms"
    "$BIN" render "$dir" --frames "$still" --backend "$BACKEND" --out "$dir.still" "${cam[@]}" --width 480 \
      --height 270 --spp 4 --no-movie >"$dir.render.log" 2>&1 &&
      cp "$dir.still/frame_$(printf '%05d' "$still").png" "$OUT/$name-$corr.png"
  done
done
(cd "$OUT" && tar cf stills.tar ./*.png 2>/dev/null) || true
