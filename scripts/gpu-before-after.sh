#!/usr/bin/env bash
# Before and after a change, on one GPU machine in one call: builds an older source tree
# (e.g. `git archive REV | tar -x -C out/base-src`) and this tree with the cuda preset, compares
# their golden outputs on the GPU (scripts/golden.sh: every output file's SHA-256), then runs the
# speed benchmarks of scripts/gpu-check.sh for both binaries in alternation and prints the
# bond-updates/s of each (springforces summed over its instantiations, and the whole step), and
# the renderer's primary rays/s (bench-render as in scripts/render-check.sh).
#   scripts/gpu-before-after.sh OLD_SOURCE_DIR|- [ROUNDS]
# Results go to $OUT/before-after (default out/before-after); exits 1 when the golden lists differ.
# BEFORE_AFTER_ENGINE_ONLY=1: only the perifrac program is built and the renderer is not timed
# (a change to the engine alone, on a short device budget).
# BEFORE_AFTER_WORKLOADS='NAME|BENCH ARGS;...': these `perifrac bench` workloads in place of the
# standard ones (e.g. 'vase|--scene scenes/vase_drop.toml --scale 4.27 --steps 1000 --warmup 100').
# BEFORE_AFTER_BINARIES='OLD NEW': two perifrac binaries built elsewhere, compared as they are and
# nothing built (OLD_SOURCE_DIR is then '-'): e.g. built on a machine with nvcc and no GPU
# (cmake -DPERIFRAC_CUDA=ON -DCMAKE_CUDA_ARCHITECTURES=90), which saves the GPU machine the build.
set -uo pipefail
cd "$(dirname "$0")/.."
rounds=${2:-2}
[[ -d .deps/bin ]] && export PATH="$PWD/.deps/bin:$PATH" LD_LIBRARY_PATH="$PWD/.deps/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PATH="$PATH:/usr/local/cuda/bin"
OUT=${OUT:-out}/before-after
mkdir -p "$OUT"
if [ -n "${BEFORE_AFTER_BINARIES:-}" ]; then
  read -r old new <<<"$BEFORE_AFTER_BINARIES"
else
  old_src=$(cd "$1" && pwd)
  [[ -e "$old_src/.deps" || ! -d .deps ]] || ln -s "$PWD/.deps" "$old_src/.deps"

  # Both builds at once (the machine has the cores for it).
  jobs=$(( $(nproc) / 2 ))
  (cmake -S "$old_src" -B build/old -G Ninja -DCMAKE_BUILD_TYPE=Release -DPERIFRAC_CUDA=ON \
     -DCMAKE_CUDA_ARCHITECTURES=90 >/dev/null && cmake --build build/old -j "$jobs" --target perifrac) \
    >"$OUT/build-old.log" 2>&1 &
  new_target=()
  [ "${BEFORE_AFTER_ENGINE_ONLY:-0}" = 1 ] && new_target=(--target perifrac)
  (cmake --preset cuda -DPERIFRAC_WERROR=ON >/dev/null && cmake --build --preset cuda -j "$jobs" "${new_target[@]}") \
    >"$OUT/build-new.log" 2>&1 &
  wait %1 || { echo "before-after: the old build failed, see $OUT/build-old.log"; exit 2; }
  wait %2 || { echo "before-after: the new build failed, see $OUT/build-new.log"; tail -20 "$OUT/build-new.log"; exit 2; }
  old=build/old/perifrac new=build/cuda/perifrac
fi

# Golden outputs on the GPU.
status=0
GOLDEN_OUT="$OUT/golden-old" scripts/golden.sh cuda "$old" >"$OUT/golden-old.txt" || status=2
GOLDEN_OUT="$OUT/golden-new" scripts/golden.sh cuda "$new" >"$OUT/golden-new.txt" || status=2
if [ $status -eq 0 ] && cmp -s "$OUT/golden-old.txt" "$OUT/golden-new.txt"; then
  echo "golden     identical: $(wc -l <"$OUT/golden-new.txt") output files of 5 scenes on the GPU"
else
    echo "golden     DIFFER (or a run failed):"
    diff "$OUT/golden-old.txt" "$OUT/golden-new.txt" | head -20
    status=1
fi

# Speed: each workload on both binaries, alternating, `rounds` times.
scene=scenes/glass_plate_projectile.toml
workloads=(
  "glass-1m|--scene $scene --scale 8 --steps 1000 --warmup 100"
  "glass-1m-explicit|--scene $scene --scale 8 --steps 1000 --warmup 100 --explicit-families"
)
for model in bond_based state_based anisotropic plastic; do
  workloads+=("lattice-$model|--lattice 100 --model $model --steps 300 --warmup 30")
done
[ -n "${BEFORE_AFTER_WORKLOADS:-}" ] && IFS=';' read -r -a workloads <<<"$BEFORE_AFTER_WORKLOADS"
# rate LOG ROW: the bond-upd/s column of the first row whose name starts with ROW.
rate() { awk -v row="$2" 'index($0, row) == 1 { for (k = NF; k > 0; --k) if ($k ~ /e[+]/) { print $k; exit } }' "$1"; }
printf '%-26s %-5s %-14s %-14s\n' workload build springforces step | tee "$OUT/speed.txt"
for w in "${workloads[@]}"; do
  name=${w%%|*} args=${w#*|}
  for ((r = 1; r <= rounds; ++r)); do
    for build in old new; do
      bin=$old
      [ $build = new ] && bin=$new
      log="$OUT/bench-$name-$build-$r.log"
      # shellcheck disable=SC2086
      "$bin" bench $args --backend cuda --out "$OUT/bench-$build" >"$log" 2>&1
      spring=$(rate "$log" "pd/springforces (all)")
      [ -z "$spring" ] && spring=$(rate "$log" "pd/springforces")
      printf '%-26s %-5s %-14s %-14s\n' "$name" $build "$spring" "$(rate "$log" "step (all kernels)")" |
        tee -a "$OUT/speed.txt"
    done
  done
done
[ "${BEFORE_AFTER_ENGINE_ONLY:-0}" = 1 ] && exit $status
# The renderer: primary rays/s at 1920 x 1080 (600k tetrahedra opaque and as glass, 600k cubes).
renders=(
  "tets|--scene slab --count 600000"
  "tets-glass|--scene slab --count 600000 --material glass"
  "cubes|--scene cubes --count 600000"
)
printf '%-26s %-5s %-14s\n' render build primary_rays/s | tee -a "$OUT/speed.txt"
for w in "${renders[@]}"; do
  name=${w%%|*} args=${w#*|}
  for ((r = 1; r <= rounds; ++r)); do
    for build in old new; do
      bin=$old
      [ $build = new ] && bin=$new
      log="$OUT/render-$name-$build-$r.log"
      # shellcheck disable=SC2086
      "$bin" bench-render $args --backend cuda --repeat 10 --no-embree --out "$OUT/bench-$build" >"$log" 2>&1
      printf '%-26s %-5s %-14s\n' "$name" $build "$(awk '/^render/ {for (k = 1; k < NF; ++k) if ($k == "primary") print $(k + 1)}' "$log")" |
        tee -a "$OUT/speed.txt"
    done
  done
done
exit $status
