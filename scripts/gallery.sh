#!/usr/bin/env bash
# The gallery: runs every shipped scene and the papers' parameter sweeps, renders a still of each
# (and with --clips every frame, made into a short MP4 where ffmpeg is present), and writes the
# index docs/gallery/README.md: scene, paper figure, particles, bonds, time per step on the device.
#
#   scripts/gallery.sh [--backend auto|cpu|cuda] [--only "NAME ..."] [--clips] [--out DIR] [--docs DIR]
#                      [--list] [--encode]
#
# --encode runs nothing: it makes the clips of frames rendered earlier by --clips (DIR/NAME/render/,
# copied from a GPU machine without ffmpeg, say), turns PNG stills in --docs into JPEG, and adds
# both to the index. Stills are 1280x720 (GALLERY_WIDTH, GALLERY_HEIGHT), clips 480x270; with
# ffmpeg present the stills are kept as JPEG (a tenth of the PNG's size).
#
# On a GPU (--backend cuda, or auto with one) the scenes run at full size, sweeps of the two
# 600k-particle scenes at a quarter; on the CPU every entry runs at its scene's CPU preview scale
# (hours on 2 cores for all of them: pick some with --only). Runs and renders go to DIR (default
# out/gallery); stills (and clips) and the index to --docs (default docs/gallery). --list prints
# the entries. Needs the perifrac binary of scripts/setup.sh (or PERIFRAC_BIN).
set -euo pipefail
cd "$(dirname "$0")/.."
# Optional programs staged by scripts/stage-deps.sh (tetgen on a machine without the package).
[[ -d .deps/bin ]] && export PATH="$PWD/.deps/bin:$PATH" LD_LIBRARY_PATH="$PWD/.deps/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

# name | scene | paper figure | overrides (;-separated) | GPU scale | CPU scale | frames | still frame
# [| camera: `perifrac render` options, where the default 3/4 view of the rest box misses the action]
# An override's value @NAME is entry NAME's run folder (an earlier entry, run in this call or left in
# DIR by an earlier one): a [[shards]] pattern's first run. Entries so named write a checkpoint.
ENTRIES=(
  "glass_plate|glass_plate_projectile|Levine Fig. 2|-|1|0.05|40|24"
  "glass_plate_ks_1e6|glass_plate_projectile|Levine Fig. 5, K_S = 1e6|projectiles[0].strength=1e6|1|0.05|24|24"
  "glass_plate_ks_1e8|glass_plate_projectile|Levine Fig. 5, K_S = 1e8|projectiles[0].strength=1e8|1|0.05|24|24"
  "vase|vase_drop|Levine Fig. 1|-|1|0.02|150|120"
  "vase_k_2.94e8|vase_drop|Levine Fig. 6, K = 2.94e8|materials.clay.bulk_modulus=2.94e8|0.25|0.02|150|120"
  "vase_k_8.82e9|vase_drop|Levine Fig. 6, K = 8.82e9|materials.clay.bulk_modulus=8.82e9|0.25|0.02|150|120"
  "vase_tau_0.01|vase_drop|Levine Fig. 8, tau = 0.01|materials.clay.strain_limit=0.01|0.25|0.02|150|120"
  "vase_tau_0.001|vase_drop|Levine Fig. 8, tau = 0.001|materials.clay.strain_limit=0.001|0.25|0.02|150|120"
  "vase_tau_0.0002|vase_drop|Levine Fig. 8, tau = 0.0002|materials.clay.strain_limit=0.0002|0.25|0.02|150|120"
  "ring|torus_voronoi_drop|Levine Fig. 3 (delta = 6 lambda)|-|1|0.1|120|100"
  "ring_delta_2|torus_voronoi_drop|Levine Fig. 7, delta = 2 lambda|materials.ceramic.horizon=2|1|0.1|120|100"
  "ring_delta_3|torus_voronoi_drop|Levine Fig. 7, delta = 3 lambda|materials.ceramic.horizon=3|1|0.1|120|100"
  "four_walls|chen_four_walls|Chen Fig. 1|-|1|0.05|60|60|--eye 0.35,0.25,-0.75 --look-at 0,-0.03,-0.02"
  "elastic_vs_plastic|chen_elastic_vs_plastic_wall|Chen Fig. 4|-|1|0.1|60|60"
  "ductile_gamma_0.1|chen_ductile_gamma|Chen Fig. 5, gamma = 0.1|-|1|0.05|60|40|--eye 0.12,0.12,-0.35 --look-at 0,0,-0.01"
  "ductile_gamma_0.15|chen_ductile_gamma|Chen Fig. 5, gamma = 0.15|materials.ductile.plastic.limit=0.15|1|0.05|60|40|--eye 0.12,0.12,-0.35 --look-at 0,0,-0.01"
  "ductile_gamma_0.2|chen_ductile_gamma|Chen Fig. 5, gamma = 0.2|materials.ductile.plastic.limit=0.2|1|0.05|60|40|--eye 0.12,0.12,-0.35 --look-at 0,0,-0.01"
  "glass_alpha_0|chen_glass_wall_alpha|Chen Fig. 7, alpha = 0|-|1|0.05|60|60|--eye 0.12,0.12,-0.35 --look-at 0,0,-0.01"
  "glass_alpha_2|chen_glass_wall_alpha|Chen Fig. 7, alpha = 2|materials.glass.damage_alpha=2|1|0.05|60|60|--eye 0.12,0.12,-0.35 --look-at 0,0,-0.01"
  "glass_alpha_4|chen_glass_wall_alpha|Chen Fig. 7, alpha = 4|materials.glass.damage_alpha=4|1|0.05|60|60|--eye 0.12,0.12,-0.35 --look-at 0,0,-0.01"
  "jello|chen_jello_bullet|Chen Fig. 8|-|1|0.1|60|40"
  "beams_poisson|chen_beams_poisson|Chen Fig. 9|-|1|0.3|150|150"
  "beams_bend|chen_beams_bend|Chen Fig. 10|-|1|0.2|60|20"
  "bar_swing|chen_bar_swing|Chen Fig. 11|-|1|0.3|60|20"
  "bar_twist|chen_bar_twist|Chen Fig. 12|-|1|0.3|36|36"
  "stretch_tear|chen_stretch_tear|Chen Fig. 14|-|1|0.1|60|50"
  "glass_pressed|chen_glass_wall_pressed|Chen Fig. 15|-|1|0.05|50|50"
  "elastic_drop|chen_elastic_drop|Chen Fig. 16|-|1|0.1|60|60|--eye 0.9,0.6,1.4 --look-at 0.1,0.05,0"
  "thin_sheet|chen_thin_sheet_tear|Chen Fig. 17|-|1|0.1|60|50"
  "glass_plate_shards|glass_plate_projectile|Levine Fig. 2 with [[shards]] (issue 31)|shards[0].size=0.02;shards[0].hold=10|1|0.05|40|24"
  "vase_shards|vase_drop|Levine Fig. 1 with [[shards]] (issue 31)|shards[0].size=0.02;shards[0].hold=10|1|0.02|150|120"
  "elastic_drop_shards|chen_elastic_drop|Chen Fig. 16 with [[shards]] (issue 31)|shards[0].size=0.05;shards[0].hold=10|1|0.1|60|60|--eye 0.9,0.6,1.4 --look-at 0.1,0.05,0"
  "glass_plate_pattern|glass_plate_projectile|Levine Fig. 2, shards along its own cracks (issue 31)|shards[0].size=0.01;shards[0].hold=10;shards[0].pattern=@glass_plate|1|0.05|40|24"
  "vase_pattern|vase_drop|Levine Fig. 1, shards along its own cracks (issue 31)|shards[0].size=0.02;shards[0].hold=10;shards[0].dust_hold=3;shards[0].pattern=@vase|1|0.02|150|120|--surface mesh"
  "elastic_drop_pattern|chen_elastic_drop|Chen Fig. 16, shards along its own cracks (issue 31)|shards[0].size=0.02;shards[0].hold=10;shards[0].dust_hold=3;shards[0].pattern=@elastic_drop|1|0.1|60|60|--eye 0.9,0.6,1.4 --look-at 0.1,0.05,0 --surface mesh"
)

usage() { sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
BACKEND=auto ONLY="" CLIPS=0 ENCODE=0 OUT=out/gallery DOCS=docs/gallery
while [[ $# -gt 0 ]]; do
  case $1 in
    --backend) BACKEND=$2; shift 2 ;;
    --only) ONLY=$2; shift 2 ;;
    --clips) CLIPS=1; shift ;;
    --encode) ENCODE=1; shift ;;
    --out) OUT=$2; shift 2 ;;
    --docs) DOCS=$2; shift 2 ;;
    --list) printf '%s\n' "${ENTRIES[@]}" | cut -d'|' -f1-3 | tr '|' '\t'; exit 0 ;;
    *) usage ;;
  esac
done
preset=$(cat build/.last-preset 2>/dev/null || echo cpu)
BIN=${PERIFRAC_BIN:-build/$preset/perifrac}
[[ -x $BIN ]] || { echo "error: no perifrac binary at '$BIN': run scripts/setup.sh first" >&2; exit 2; }
if [[ $BACKEND == auto ]]; then
  BACKEND=cpu
  "$BIN" info 2>/dev/null | grep -q '^cuda *available' && BACKEND=cuda
fi
mkdir -p "$OUT" "$DOCS"
WIDTH=${GALLERY_WIDTH:-1280} HEIGHT=${GALLERY_HEIGHT:-720} SPP=8
CLIP_WIDTH=480 CLIP_HEIGHT=270 CLIP_SPP=4

# The index: rows of this run, and of entries not run this time as the index had them.
write_index() {
  local line key entry name
  if [[ -f $DOCS/README.md ]]; then
    while IFS= read -r line; do
      key=$(echo "$line" | cut -d'|' -f2 | tr -d ' ')
      [[ -n $key && -z ${rows[$key]+x} ]] && rows[$key]=$line
    done < <(grep '^| [a-z]' "$DOCS/README.md" | grep -v '^| entry ')
  fi
  {
    if [[ $ENCODE == 1 && -f $DOCS/README.md ]]; then
      sed -n '1,/^| entry /p' "$DOCS/README.md" | sed '$d'  # encoding runs nothing: the header stays
    else
      echo "# Gallery"
      echo
      echo "Every shipped scene and the papers' parameter sweeps, made by \`scripts/gallery.sh\` on"
      echo "$(date -u +%Y-%m-%d) (last run: backend $BACKEND, git ${PERIFRAC_GIT_REV:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)})."
      echo "Time per step: all kernels of a step, from the run's kernel table. Stills are ${WIDTH}x${HEIGHT},"
      echo "$SPP samples per pixel, rendered by \`perifrac render\` on the same backend (clips ${CLIP_WIDTH}x${CLIP_HEIGHT})."
      echo
    fi
    echo "| entry | figure | scene and overrides | particles | bonds | ms per step | device | still |"
    echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
    for entry in "${ENTRIES[@]}"; do
      name=${entry%%|*}
      [[ -n ${rows[$name]+x} ]] || continue
      line=${rows[$name]% |}
      line=${line% \[clip\]($name.mp4)}
      [[ -f $DOCS/$name.jpg ]] && line=${line//"($name.png)"/"($name.jpg)"}
      [[ -f $DOCS/$name.mp4 ]] && line+=" [clip]($name.mp4)"
      echo "$line |"
    done
    # Sections written by hand after the table (## ...) are kept.
    if [[ -f $DOCS/README.md ]] && grep -q '^## ' "$DOCS/README.md"; then
      echo
      sed -n '/^## /,$p' "$DOCS/README.md"
    fi
  } >"$DOCS/README.md.tmp"
  mv "$DOCS/README.md.tmp" "$DOCS/README.md"
}

# The still of entry $1 as JPEG where ffmpeg is present (the PNG removed), else left as PNG.
compress_still() {
  command -v ffmpeg >/dev/null && [[ -f $DOCS/$1.png ]] || return 0
  ffmpeg -loglevel error -y -i "$DOCS/$1.png" -q:v 3 "$DOCS/$1.jpg" && rm -f "$DOCS/$1.png"
}

# The clip of entry $1 from its rendered frames, where ffmpeg is present.
make_clip() {
  if command -v ffmpeg >/dev/null; then
    ffmpeg -loglevel error -y -framerate 12 -i "$OUT/$1/render/frame_%05d.png" -pix_fmt yuv420p \
      -c:v libx264 -crf 30 "$DOCS/$1.mp4"
  else
    echo "   no ffmpeg: the clip's frames are in $OUT/$1/render/ (make it later with --encode)"
  fi
}

# Whether entry $1 is one of --only (all without it).
selected() { [[ -z $ONLY || " $ONLY " == *" $1 "* ]]; }

declare -A rows
if [[ $ENCODE == 1 ]]; then
  for entry in "${ENTRIES[@]}"; do
    name=${entry%%|*}
    selected "$name" || continue
    compress_still "$name"
    [[ -f $OUT/$name/render/frame_00000.png ]] || continue
    echo "== $name: clip from $OUT/$name/render/"
    make_clip "$name"
  done
  write_index
  echo "gallery: $DOCS/README.md"
  exit 0
fi
for entry in "${ENTRIES[@]}"; do
  IFS='|' read -r name scene figure sets gpu_scale cpu_scale frames still camera <<<"$entry"
  read -ra cam <<<"${camera:-}"
  selected "$name" || continue
  scale=$gpu_scale
  [[ $BACKEND == cpu ]] && scale=$cpu_scale
  args=(run --overwrite "scenes/$scene.toml" --backend "$BACKEND" --scale "$scale" --frames "$frames" --out "$OUT/$name"
        --set output.vtk=false)
  # A pattern's first run keeps its checkpoint.
  printf '%s\n' "${ENTRIES[@]}" | grep -q "=@$name[;|]" && args+=(--checkpoint-every "$frames")
  if [[ $sets != - ]]; then
    IFS=';' read -ra list <<<"$sets"
    for s in "${list[@]}"; do
      if [[ $s == *=@* ]]; then  # @NAME: that entry's run folder
        source_dir=$OUT/${s#*=@}
        [[ -f $source_dir/checkpoint.pck ]] || { echo "   $name needs entry ${s#*=@} run first (no $source_dir/checkpoint.pck)"; continue 2; }
        s="${s%%=@*}=\"$(cd "$source_dir" && pwd)\""
      fi
      args+=(--set "$s")
    done
  fi
  echo "== $name ($figure): perifrac ${args[*]}"
  if ! "$BIN" "${args[@]}" >"$OUT/$name.log" 2>&1; then
    echo "   failed (exit $?): $(grep -m1 'error' "$OUT/$name.log" || tail -1 "$OUT/$name.log")"
    rows[$name]="| $name | $figure | failed: see $OUT/$name.log | | | | | |"
    write_index
    continue
  fi
  # The still: the chosen frame alone, rendered on the same backend.
  "$BIN" render "$OUT/$name" --frames "$still" --backend "$BACKEND" --out "$OUT/$name.still" "${cam[@]}" --width $WIDTH \
    --height $HEIGHT --spp $SPP >"$OUT/$name.render.log" 2>&1
  rm -f "$DOCS/$name.jpg"
  cp "$OUT/$name.still/frame_$(printf '%05d' "$still").png" "$DOCS/$name.png"
  compress_still "$name"
  if [[ $CLIPS == 1 ]]; then
    "$BIN" render "$OUT/$name" --backend "$BACKEND" "${cam[@]}" --width $CLIP_WIDTH --height $CLIP_HEIGHT --spp $CLIP_SPP \
      >>"$OUT/$name.render.log" 2>&1
    make_clip "$name"
  fi
  particles=$(sed -n 's/^particles  \([0-9]*\) .*/\1/p' "$OUT/$name.log")
  bonds=$(sed -n 's/^bonds      \([0-9]*\) .*/\1/p' "$OUT/$name.log")
  step_ms=$(sed -n 's/^step (all kernels) *[0-9]* *\([0-9.]*\) .*/\1/p' "$OUT/$name.log")
  device=$(sed -n 's/^device     //p' "$OUT/$name.log")
  desc="$scene.toml"
  [[ $sets == - ]] || desc+=" --set ${sets//;/ --set }"
  [[ $scale == 1 ]] || desc+=" --scale $scale"
  rows[$name]="| $name | $figure | $desc | $particles | $bonds | $step_ms | $device | ![$name]($name.png) |"
  write_index
done
write_index
echo "gallery: $DOCS/README.md"
