#!/usr/bin/env bash
# Everything a GPU change needs, in one call on a GPU machine: build (cuda preset), the
# gpu-labelled tests, the CPU suite of the same build, a CPU-vs-GPU equivalence check of a
# scene through the command line, compute-sanitizer (memcheck, racecheck) on a small scene,
# and the benchmarks. Prints a short table last. Logs and results go to $OUT (default
# out/gpu-check). Header-only dependencies missing there travel in .deps (scripts/stage-deps.sh).
set -uo pipefail
cd "$(dirname "$0")/.."
# Optional programs staged by scripts/stage-deps.sh (tetgen on a machine without the package).
[[ -d .deps/bin ]] && export PATH="$PWD/.deps/bin:$PATH" LD_LIBRARY_PATH="$PWD/.deps/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PATH="$PATH:/usr/local/cuda/bin"
OUT=${OUT:-out}/gpu-check
mkdir -p "$OUT"
bin=build/cuda/perifrac
scene=scenes/glass_plate_projectile.toml
rows=()

# step NAME COMMAND...: runs the command with its output in $OUT/NAME.log, records pass/fail and time
# (also in $OUT/rows/NAME). With GPU_CHECK_RESUME=1 a step that passed in an earlier call on the
# same machine and $OUT keeps its row and is not run again: a check cut off by a time limit goes
# on where it stopped. GPU_CHECK_SKIP="NAME ..." leaves those steps out, listed as skipped.
mkdir -p "$OUT/rows"
step() {
  local name=$1; shift
  if [[ " ${GPU_CHECK_SKIP:-} " == *" $name "* ]]; then
    rows+=("$(printf '%-22s %-5s' "$name" skip)  (GPU_CHECK_SKIP)")
    echo "== $name: skipped"
    return
  fi
  if [[ "${GPU_CHECK_RESUME:-0}" == 1 && -f "$OUT/rows/$name" ]] && grep -q "^$name  *pass " "$OUT/rows/$name"; then
    rows+=("$(cat "$OUT/rows/$name") (earlier call)")
    echo "== $name: pass (earlier call)"
    return
  fi
  local t0=$SECONDS
  if "$@" >"$OUT/$name.log" 2>&1; then status=pass; else status=FAIL; fi
  rows+=("$(printf '%-22s %-5s %5ds  %s' "$name" "$status" $((SECONDS - t0)) "$(tail -n 1 "$OUT/$name.log" | cut -c1-90)")")
  printf '%s\n' "${rows[-1]}" >"$OUT/rows/$name"
  echo "== $name: $status"
}

step build bash -c "cmake --preset cuda -DPERIFRAC_WERROR=ON >/dev/null && cmake --build --preset cuda -j \$(nproc)"
nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv,noheader >"$OUT/device.txt" 2>&1
step gpu-tests build/cuda/tests/perifrac_gpu_tests
step cpu-tests build/cuda/tests/perifrac_tests
step equiv-cpu "$bin" run --overwrite "$scene" --backend cpu --scale 0.05 --frames 3 --out "$OUT/equiv-cpu"
step equiv-gpu "$bin" run --overwrite "$scene" --backend cuda --scale 0.05 --frames 3 --out "$OUT/equiv-gpu"
step equiv-compare "$bin" compare "$OUT/equiv-cpu" "$OUT/equiv-gpu"
walls=scenes/chen_four_walls.toml
step equiv-walls-cpu "$bin" run --overwrite "$walls" --backend cpu --scale 0.02 --frames 4 --out "$OUT/equiv-walls-cpu"
step equiv-walls-gpu "$bin" run --overwrite "$walls" --backend cuda --scale 0.02 --frames 4 --out "$OUT/equiv-walls-gpu"
step equiv-walls-compare "$bin" compare "$OUT/equiv-walls-cpu" "$OUT/equiv-walls-gpu"
# Scripted anchors (a turning grip) and pre-cracks with moving grips, state-based.
for extra in chen_bar_twist:0.3 chen_thin_sheet_tear:0.1; do
  name=${extra%%:*} scale=${extra#*:}
  step "equiv-$name-cpu" "$bin" run --overwrite "scenes/$name.toml" --backend cpu --scale "$scale" --frames 3 \
    --out "$OUT/equiv-$name-cpu"
  step "equiv-$name-gpu" "$bin" run --overwrite "scenes/$name.toml" --backend cuda --scale "$scale" --frames 3 \
    --out "$OUT/equiv-$name-gpu"
  step "equiv-$name-compare" "$bin" compare "$OUT/equiv-$name-cpu" "$OUT/equiv-$name-gpu"
done
# The ghost surface correction (cuda/kernels/surface_ghosts.h) on the twisted rubber bar.
ghost_twist=(scenes/chen_bar_twist.toml --scale 0.3 --set 'materials.rubber.surface_correction="ghosts"')
step equiv-ghosts-cpu "$bin" run --overwrite "${ghost_twist[@]}" --frames 3 --backend cpu --out "$OUT/equiv-ghosts-cpu"
step equiv-ghosts-gpu "$bin" run --overwrite "${ghost_twist[@]}" --frames 3 --backend cuda --out "$OUT/equiv-ghosts-gpu"
step equiv-ghosts-compare "$bin" compare "$OUT/equiv-ghosts-cpu" "$OUT/equiv-ghosts-gpu"
# Colliders: a wall resting on frictional ground, hit by a scripted sphere from the first frame.
# Two frames (13% of the bonds broken): in the third the coarse wall shatters (43% broken) and the
# CPU's and GPU's roundings grow into different debris (measured 2026-11-26 on an H100, surface
# correction on: displacement 2.9e-5, 3.4e-4, 9.9e-3 after frames 1, 2, 3).
ball=(scenes/wrecking_ball.toml --scale 0.05 --frames 2 --set 'colliders[1].path=[[0, 0, 0.55, -0.36], [0.2, 0, 0.55, 0.44]]')
step equiv-colliders-cpu "$bin" run --overwrite "${ball[@]}" --backend cpu --out "$OUT/equiv-colliders-cpu"
step equiv-colliders-gpu "$bin" run --overwrite "${ball[@]}" --backend cuda --out "$OUT/equiv-colliders-gpu"
step equiv-colliders-compare "$bin" compare "$OUT/equiv-colliders-cpu" "$OUT/equiv-colliders-gpu"
# A mesh collider: the steel wedge (its distance grid) driven into the stone block from frame 1.
wedge=(scenes/wedge_splits_block.toml --scale 0.1 --frames 3)
step equiv-mesh-cpu "$bin" run --overwrite "${wedge[@]}" --backend cpu --out "$OUT/equiv-mesh-cpu"
step equiv-mesh-gpu "$bin" run --overwrite "${wedge[@]}" --backend cuda --out "$OUT/equiv-mesh-gpu"
step equiv-mesh-compare "$bin" compare "$OUT/equiv-mesh-cpu" "$OUT/equiv-mesh-gpu"
# A free collider: the iron ball, pushed back by the wall it hits from the first frame. One frame
# (1 ms of contact): after it this coarse wall shatters into grit, where the order of the sums in the
# ball's reaction grows into different cracks (measured 2026-11-26 on an H200: displacement 3.3e-6
# after frame 1, 6e-3 after frame 2).
cannon=(scenes/cannonball_wall.toml --scale 0.1 --set 'colliders[1].center=[0, 0.55, -0.26]')
step equiv-free-cpu "$bin" run --overwrite "${cannon[@]}" --frames 1 --backend cpu --out "$OUT/equiv-free-cpu"
step equiv-free-gpu "$bin" run --overwrite "${cannon[@]}" --frames 1 --backend cuda --out "$OUT/equiv-free-gpu"
step equiv-free-compare "$bin" compare "$OUT/equiv-free-cpu" "$OUT/equiv-free-gpu"
# Determinism (two runs, identical files) and checkpoint/resume (bit for bit) on the GPU.
same_files() {
  local a=$1 b=$2; shift 2
  for f in "$@"; do cmp "$a/$f" "$b/$f" || return 1; done
  echo "identical: $*"
}
# CUDA graphs of the step (cuda/engine/step_graphs.h): the swinging bar, whose steps go as graphs,
# against the CPU, and bit for bit against the same run launched step by step.
swing=(scenes/chen_bar_swing.toml --scale 0.3)
step equiv-graphs-cpu "$bin" run --overwrite "${swing[@]}" --frames 2 --backend cpu --out "$OUT/equiv-graphs-cpu"
step equiv-graphs-gpu "$bin" run --overwrite "${swing[@]}" --frames 2 --backend cuda --out "$OUT/equiv-graphs-gpu"
step equiv-graphs-compare "$bin" compare "$OUT/equiv-graphs-cpu" "$OUT/equiv-graphs-gpu"
step graphs-off-run env PERIFRAC_STEP_GRAPHS=off "$bin" run --overwrite "${swing[@]}" --frames 2 \
  --backend cuda --out "$OUT/graphs-off"
step graphs-off-compare same_files "$OUT/equiv-graphs-gpu" "$OUT/graphs-off" frame_00002.pfr energy.csv
# Contact lists rebuilt for the movers alone (cuda/kernels/contact_relist.h) against every list
# built at every rebuild: the vase through its impact, bit for bit.
vase_impact=(scenes/vase_drop.toml --scale 0.1 --frames 12)
step relist-run "$bin" run --overwrite "${vase_impact[@]}" --backend cuda --out "$OUT/relist"
step relist-full-run env PERIFRAC_CONTACT_REBUILD=full "$bin" run --overwrite "${vase_impact[@]}" --backend cuda \
  --out "$OUT/relist-full"
step relist-compare same_files "$OUT/relist" "$OUT/relist-full" frame_00012.pfr energy.csv fragments_00012.pfg
step determinism-run "$bin" run --overwrite "$scene" --backend cuda --scale 0.05 --frames 3 --out "$OUT/equiv-gpu-again"
step determinism-compare same_files "$OUT/equiv-gpu" "$OUT/equiv-gpu-again" frame_00003.pfr energy.csv fragments_00003.pfg
step resume-first "$bin" run --overwrite "$walls" --backend cuda --scale 0.02 --frames 2 --checkpoint-every 2 --out "$OUT/resume"
step resume-rest "$bin" run --resume "$OUT/resume" --frames 4
step resume-compare same_files "$OUT/equiv-walls-gpu" "$OUT/resume" frame_00004.pfr energy.csv fragments_00004.pfg
# Runs over several MPI ranks (sharing the GPUs there are) against one rank, bit for bit.
if command -v mpirun >/dev/null; then
  step mpi-equivalence env MPI_EQUIVALENCE_OUT="$OUT/mpi-equivalence" scripts/mpi-equivalence.sh "$bin" cuda
fi
# compute-sanitizer on a small scene of each material model, and on the renderer.
for tool in memcheck racecheck; do
  step "sanitizer-$tool" compute-sanitizer --tool "$tool" --error-exitcode 9 \
    "$bin" run --overwrite "$scene" --backend cuda --scale 0.01 --frames 2 --steps-per-frame 10 --out "$OUT/sanitizer"
  step "sanitizer-$tool-plastic" compute-sanitizer --tool "$tool" --error-exitcode 9 \
    "$bin" run --overwrite scenes/chen_four_walls.toml --backend cuda --scale 0.005 --frames 1 --steps-per-frame 10 \
    --out "$OUT/sanitizer-plastic"
  step "sanitizer-$tool-colliders" compute-sanitizer --tool "$tool" --error-exitcode 9 \
    "$bin" run --overwrite "${cannon[@]}" --backend cuda --frames 1 --steps-per-frame 10 --out "$OUT/sanitizer-colliders"
  step "sanitizer-$tool-ghosts" compute-sanitizer --tool "$tool" --error-exitcode 9 \
    "$bin" run --overwrite "${ghost_twist[@]}" --backend cuda --frames 1 --steps-per-frame 10 --out "$OUT/sanitizer-ghosts"
  step "sanitizer-$tool-graphs" compute-sanitizer --tool "$tool" --error-exitcode 9 \
    "$bin" run --overwrite "${swing[@]}" --backend cuda --frames 1 --steps-per-frame 70 --out "$OUT/sanitizer-graphs"
  step "sanitizer-$tool-render" compute-sanitizer --tool "$tool" --error-exitcode 9 \
    "$bin" render "$OUT/sanitizer" --backend cuda --width 64 --height 48 --spp 1
done
step bench-glass "$bin" bench --scene "$scene" --backend cuda --steps 2000 --warmup 200 --out "$OUT/bench"
# The issue-5 full-step workload: the glass plate at 1M particles, the projectile arriving.
step bench-glass-1m "$bin" bench --scene "$scene" --scale 8 --backend cuda --steps 1000 --warmup 100 --out "$OUT/bench"
# What lattice families save: the same workloads with every partner found through its index.
step bench-glass-1m-explicit "$bin" bench --scene "$scene" --scale 8 --backend cuda --steps 1000 --warmup 100 \
  --explicit-families --out "$OUT/bench"
for model in bond_based state_based anisotropic plastic; do
  step "bench-lattice-$model" "$bin" bench --lattice 100 --model "$model" --backend cuda --steps 300 --warmup 30 \
    --out "$OUT/bench"
  step "bench-lattice-$model-explicit" "$bin" bench --lattice 100 --model "$model" --backend cuda --steps 300 \
    --warmup 30 --explicit-families --out "$OUT/bench"
done
# Issue 27's mesh-filled workloads: the vase at Levine's size (577k TetGen tets) before and while it
# meets the floor (its breaking pass), and the torus of 519k Voronoi cells.
vase=(--scene scenes/vase_drop.toml --scale 4.27 --backend cuda --out "$OUT/bench")
step bench-vase "$bin" bench "${vase[@]}" --steps 1000 --warmup 100
step bench-vase-impact "$bin" bench "${vase[@]}" --steps 3000 --warmup 8000
step bench-torus "$bin" bench --scene scenes/torus_voronoi_drop.toml --scale 31.5 --backend cuda --steps 300 \
  --warmup 30 --out "$OUT/bench"
# What the ghost surface correction costs per step: the twisted bar (every particle within a
# horizon of its surface) with and without it.
for sc in false '"ghosts"'; do
  step "bench-twist-surface-$sc" "$bin" bench --scene scenes/chen_bar_twist.toml --scale 100 \
    --set "materials.rubber.surface_correction=$sc" --backend cuda --steps 300 --warmup 30 --out "$OUT/bench"
done
# Launch-bound: the swinging bar (3,840 particles) with and without graphs of the step.
for graphs in on off; do
  step "bench-swing-graphs-$graphs" "$bin" bench --scene scenes/chen_bar_swing.toml --step-graphs "$graphs" \
    --backend cuda --steps 4000 --warmup 400 --out "$OUT/bench"
done
step glass-full "$bin" run --overwrite "$scene" --backend cuda --out "$OUT/glass-full"

{
  echo "gpu-check on $(cat "$OUT/device.txt"), $(date -u +%Y-%m-%dT%H:%M:%SZ), git ${PERIFRAC_GIT_REV:-$(git rev-parse --short HEAD 2>/dev/null || echo unknown)}"
  printf '%s\n' "${rows[@]}"
  grep -h "equivalence" "$OUT/gpu-tests.log" || true
  grep -h "ERROR SUMMARY" "$OUT"/sanitizer-*.log || true
} >"$OUT/summary.txt"
echo
cat "$OUT/summary.txt"
for row in "${rows[@]}"; do [[ "$row" == *" FAIL "* ]] && exit 1; done
exit 0
