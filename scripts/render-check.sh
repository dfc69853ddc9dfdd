#!/usr/bin/env bash
# The renderer's GPU checks in one call on a GPU machine: build (cuda preset), the CPU-vs-GPU
# image tests (PSNR >= 40 dB), a run that renders as it goes on the GPU, compute-sanitizer
# memcheck on small renders (run frames with cubes and trimtopes; synthetic tetrahedra, opaque
# and glass), and `perifrac bench-render` at 1920 x 1080 on CUDA: 600k tetrahedra (the issue's
# target, >= 1e9 primary rays/s; as rendered, and with the hidden ones kept in the kd-tree),
# 600k cubes, and the tetrahedra as glass. Prints a short table
# last. Logs and results go to $OUT/render-check (default out/render-check).
set -uo pipefail
cd "$(dirname "$0")/.."
export PATH="$PATH:/usr/local/cuda/bin"
OUT=${OUT:-out}/render-check
mkdir -p "$OUT"
bin=build/cuda/perifrac
rows=()

# step NAME COMMAND...: runs the command with its output in $OUT/NAME.log, records pass/fail and time.
step() {
  local name=$1; shift
  local t0=$SECONDS
  if "$@" >"$OUT/$name.log" 2>&1; then status=pass; else status=FAIL; fi
  rows+=("$(printf '%-24s %-5s %5ds  %s' "$name" "$status" $((SECONDS - t0)) "$(tail -n 1 "$OUT/$name.log" | cut -c1-90)")")
  echo "== $name: $status"
}

step build bash -c "cmake --preset cuda >/dev/null && cmake --build --preset cuda -j \$(nproc)"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader >"$OUT/device.txt" 2>&1
step render-tests build/cuda/tests/perifrac_tests --gtest_filter='CudaRenderer.*'
# A run with a [render] block on the GPU, then the memory checker on renders of its frames.
scene="$OUT/glass_render.toml"
{ cat scenes/glass_plate_projectile.toml; printf '\n[render]\nwidth = 320\nheight = 180\nspp = 2\nevery = 2\n'; } >"$scene"
step live-render "$bin" run --overwrite "$scene" --backend cuda --scale 0.02 --frames 4 --steps-per-frame 50 --out "$OUT/live"
step torus-run "$bin" run --overwrite scenes/torus_voronoi_drop.toml --backend cuda --scale 0.05 --frames 2 --steps-per-frame 20 \
  --out "$OUT/torus"
for dir in live torus; do
  step "memcheck-render-$dir" compute-sanitizer --tool memcheck --error-exitcode 9 \
    "$bin" render "$OUT/$dir" --backend cuda --width 64 --height 48 --spp 1 --no-movie --out "$OUT/memcheck-$dir"
done
for material in opaque glass; do
  step "memcheck-bench-$material" compute-sanitizer --tool memcheck --error-exitcode 9 \
    "$bin" bench-render --count 6000 --width 64 --height 48 --repeat 1 --material "$material" --backend cuda \
    --no-embree --out "$OUT/bench-small"
done
# The figures: 1920 x 1080, best of 10 renders after a warm-up.
step bench-tets "$bin" bench-render --scene slab --count 600000 --backend cuda --repeat 10 --no-embree --out "$OUT/bench"
step bench-tets-all "$bin" bench-render --scene slab --count 600000 --backend cuda --repeat 10 --no-embree \
  --keep-hidden --out "$OUT/bench"
step bench-cubes "$bin" bench-render --scene cubes --count 600000 --backend cuda --repeat 10 --no-embree --out "$OUT/bench"
step bench-tets-glass "$bin" bench-render --scene slab --count 600000 --material glass --backend cuda --repeat 10 \
  --no-embree --out "$OUT/bench"

echo
echo "render-check on $(cat "$OUT/device.txt"), $(date -u +%Y-%m-%dT%H:%M:%SZ), git ${PERIFRAC_GIT_REV:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)}"
printf '%s\n' "${rows[@]}"
grep -h "PSNR" "$OUT/render-tests.log" || true
for b in bench-tets bench-tets-all bench-cubes bench-tets-glass; do
  echo "-- $b"
  grep -hE "^(bench-render|hidden|kd-tree|render |per frame|trace-only)" "$OUT/$b.log" || true
done
for row in "${rows[@]}"; do [[ "$row" == *" FAIL "* ]] && exit 1; done
exit 0
