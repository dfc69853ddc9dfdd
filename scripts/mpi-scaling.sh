#!/usr/bin/env bash
# Scaling over the GPUs of one host: `perifrac bench` of the glass plate under mpirun, strong (the
# same particles on 1, 2, 4 ... GPUs) and weak (the particles grow with the GPUs), with the halo
# as configured by default (NCCL, overlapped with the interior forces) and, for comparison, staged
# through host memory and not overlapped. Prints a table (bond-updates/s end to end, efficiency
# against one GPU) after the logs; the JSON of each run goes to $OUT/mpi-scaling/json.
#   scripts/mpi-scaling.sh [BINARY] [MAX_GPUS]
#   MPI_SCALING_RUNS="strong 1 128 200; weak 4 512 200" scripts/mpi-scaling.sh ...   (only these runs)
# Glass plate sizes: --scale 32 is 4.12M particles (0.46G bonds), 128 is 16.8M, 512 is 67M,
# 704 is 92M (1.0e10 bonds). The scene's dt (2^-23 s) is past the stable step from --scale 64 on
# (the horizon shrinks with the spacing), so every run takes dt = "auto", half the stable step.
set -uo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/cuda/perifrac}
max=${2:-$(nvidia-smi -L 2>/dev/null | wc -l)}
OUT=${OUT:-out}/mpi-scaling
mkdir -p "$OUT/json"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 NCCL_NVLS_ENABLE=0
# Threads per rank for the host set-up (scene, partition, tables): the host's cores shared out.
threads=${OMP_NUM_THREADS:-}
cores=$(nproc)
scene=scenes/glass_plate_projectile.toml
rows=()

# run NAME RANKS SCALE STEPS [VAR=VALUE ...]: one bench; its rate into the table.
run() {
  local name=$1 ranks=$2 scale=$3 steps=$4
  shift 4
  local env=()
  for kv in "$@"; do env+=(-x "$kv"); done
  local log="$OUT/$name-r$ranks-s$scale.log"
  local omp=${threads:-$((cores / ranks > 1 ? cores / ranks : 1))}
  echo "== $name: $ranks GPUs, scale $scale, $omp threads per rank $*" | tee "$log"
  mpirun -np "$ranks" --bind-to none -x NCCL_NVLS_ENABLE -x OMP_NUM_THREADS="$omp" "${env[@]}" "$bin" bench \
    --scene "$scene" --set 'simulation.dt="auto"' --backend cuda --scale "$scale" --steps "$steps" --warmup 20 \
    --out "$OUT/json" >>"$log" 2>&1
  grep -E "^(ranks|halo|size|wall|rank )" "$log"
  local rate particles
  rate=$(sed -n 's/^wall .*: \([0-9.e+]*\) bond-updates.*/\1/p' "$log")
  particles=$(sed -n 's/^size *\([0-9]*\) particles.*/\1/p' "$log")
  rows+=("$name $ranks $scale ${particles:-?} ${rate:-failed}")
}

gpus=(1)
for g in 2 4 8; do [ "$g" -le "$max" ] && gpus+=("$g"); done
if [ -n "${MPI_SCALING_RUNS:-}" ]; then
  # Only these runs: "NAME GPUS SCALE STEPS [VAR=VALUE ...]; ..." (e.g. "strong 1 128 200; weak 4 512 200").
  IFS=';' read -ra picked <<<"$MPI_SCALING_RUNS"
  for entry in "${picked[@]}"; do
    read -ra args <<<"$entry"
    [ "${#args[@]}" -ge 4 ] && run "${args[@]}"
  done
else
  for g in "${gpus[@]}"; do run strong "$g" 32 400; done
  for g in "${gpus[@]:1}"; do
    run strong-host-halo "$g" 32 400 PERIFRAC_HALO=host
    run strong-not-overlapped "$g" 32 400 PERIFRAC_HALO_OVERLAP=0
  done
  for g in "${gpus[@]}"; do run strong "$g" 128 200; done
  for g in "${gpus[@]:1}"; do run weak "$g" $((128 * g)) 200; done
  # Past 1e10 bonds (92M particles) on every GPU of the host.
  run large "${gpus[-1]}" 704 100
fi

# Efficiency: rate / (GPUs x one GPU's rate): strong against one GPU at the same scale; weak and
# large against one GPU at 128.
echo
printf '%-22s %5s %6s %10s %12s %10s\n' run GPUs scale particles bond-upd/s efficiency
declare -A one
for row in "${rows[@]}"; do
  read -r name g scale n rate <<<"$row"
  [ "$g" = 1 ] && one[$scale]=$rate
done
for row in "${rows[@]}"; do
  read -r name g scale n rate <<<"$row"
  base=${one[$scale]:-}
  [ "$name" = weak ] || [ "$name" = large ] && base=${one[128]:-}
  eff=$(awk -v r="$rate" -v b="$base" -v g="$g" 'BEGIN { if (b > 0 && r > 0) printf "%.0f%%", 100 * r / (g * b); else print "-" }')
  printf '%-22s %5s %6s %10s %12s %10s\n' "$name" "$g" "$scale" "$n" "$rate" "$eff"
done
