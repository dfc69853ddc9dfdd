#!/usr/bin/env bash
# Stability stress test (docs/validation.md, "Stability"): runs the scenes of scenes/validation/
# stress_*.toml through `perifrac run` over dt / dt_c from 0.25 to 2.5 (above 1 with
# --allow-unstable-dt), contact between bodies whose stiffnesses differ 10^4 times, projectile
# strengths K_S up to 1e20 and dense collisions, and sorts each run into
#   stable     exit 0, every energy.csv value finite and the final energy balance within 10%;
#   drift      exit 0 and finite, but the energy balance off by more than 10% (the watchdog stops
#              a run past 100%, or past 10% when dt exceeds the stable step): listed and
#              counted, a warning, not a failure;
#   watchdog   exit 3 with the blow-up message naming the step;
#   FAILURE    anything else: a crash, a hang (timeout), a NaN/inf in the output, exit 3 without
#              the message, or another exit code. There must be none.
# Writes stability.csv and stability.md to bench/accuracy/ (or --out); exits 1 on any FAILURE.
#   scripts/stress-stability.sh BUILD [--out DIR] [--backend cpu|cuda|auto] [--timeout S]
set -uo pipefail
cd "$(dirname "$0")/.."

[[ $# -ge 1 ]] || { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
BIN=$1; [[ -d $BIN ]] && BIN=$BIN/perifrac; shift
OUT=bench/accuracy BACKEND=cpu TIMEOUT=300
while [[ $# -gt 0 ]]; do
  case $1 in
    --out) OUT=$2; shift 2 ;;
    --backend) BACKEND=$2; shift 2 ;;
    --timeout) TIMEOUT=$2; shift 2 ;;
    *) echo "error: unknown option $1" >&2; exit 2 ;;
  esac
done
[[ -x $BIN ]] || { echo "error: no perifrac binary at '$BIN'" >&2; exit 2; }
mkdir -p "$OUT"
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
CSV=$OUT/stability.csv
echo "scene,dt_over_dtc,projectile_strength,particles,exit_code,outcome,wall_s,detail" >"$CSV"

# The smallest dt_c over a scene's materials, from the start-up report of a zero-frame run.
critical_dt() {
  "$BIN" run --overwrite "$1" --frames 0 --out "$WORK/probe" --backend "$BACKEND" 2>/dev/null |
    sed -n 's/.*dt_c \([0-9.e+-]*\) s.*/\1/p' | sort -g | head -1
}

# One run: scene file, dt fraction, projectile strength ("-" to keep the scene's).
run_case() {
  local scene=$1 frac=$2 ks=$3 name dtc dt file log code outcome detail particles t0 wall
  name=$(basename "$scene" .toml)
  file=$WORK/$name.toml log=$WORK/$name.log
  dtc=$(critical_dt "$scene")
  dt=$(awk -v a="$dtc" -v f="$frac" 'BEGIN { printf "%.6e", a * f }')
  sed "s/^dt = .*/dt = $dt/" "$scene" >"$file"
  [[ $ks != - ]] && sed -i "s/^strength = .*/strength = $ks/" "$file"
  t0=$(date +%s.%N)
  timeout "$TIMEOUT" "$BIN" run --overwrite "$file" --out "$WORK/out-$name" --backend "$BACKEND" --allow-unstable-dt \
    >"$log" 2>&1
  code=$?
  wall=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  particles=$(sed -n 's/^particles *\([0-9]*\).*/\1/p' "$log")
  if [[ $code == 0 ]]; then
    if [[ -f $WORK/out-$name/energy.csv ]] && ! grep -qiE 'nan|inf' "$WORK/out-$name/energy.csv"; then
      detail="energy balance $(grep -o 'energy balance [^ ]*' "$log" | tail -1 | cut -d' ' -f3)"
      outcome=$(awk -v b="${detail##* }" 'BEGIN { b += 0; print (b > 10 || b < -10) ? "drift" : "stable" }')
    else
      outcome=FAILURE detail="exit 0 but non-finite or missing energy.csv"
    fi
  elif [[ $code == 3 ]] && grep -q 'numerical blow-up.*step [0-9]' "$log"; then
    outcome=watchdog detail=$(grep -o 'by step [0-9]*' "$log" | head -1)
  elif [[ $code == 124 ]]; then
    outcome=FAILURE detail="hang: killed after $TIMEOUT s"
  else
    outcome=FAILURE detail="exit $code: $(grep -m1 -i 'error' "$log" | tr ',' ';' | cut -c1-120)"
  fi
  echo "$name,$frac,$ks,$particles,$code,$outcome,$wall,$detail" >>"$CSV"
  printf '%-24s dt %4s dt_c  K_S %-6s exit %3s  %-8s %6s s  %s\n' "$name" "$frac" "$ks" "$code" "$outcome" \
    "$wall" "$detail"
}

for scene in scenes/validation/stress_drop.toml scenes/validation/stress_stiffness_ratio.toml \
  scenes/validation/stress_dense.toml; do
  for frac in 0.25 0.5 0.9 1.0 1.25 1.5 2.0 2.5; do run_case "$scene" "$frac" -; done
done
for ks in 1e7 1e12 1e16 1e20; do
  for frac in 0.5 0.9 1.5; do run_case scenes/validation/stress_projectile.toml "$frac" "$ks"; done
done

# Markdown table.
failures=$(awk -F, 'NR > 1 && $6 == "FAILURE"' "$CSV" | wc -l)
{
  echo "# Stability stress test"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "- device: $(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -1) ($(nproc) cores), backend $BACKEND"
  echo "- binary: \`$BIN\`; scenes: \`scenes/validation/stress_*.toml\`; method: docs/validation.md"
  echo "- totals: $(awk -F, 'NR > 1 && $6 == "stable"' "$CSV" | wc -l) stable," \
    "$(awk -F, 'NR > 1 && $6 == "drift"' "$CSV" | wc -l) finite but with the energy balance off by > 10%," \
    "$(awk -F, 'NR > 1 && $6 == "watchdog"' "$CSV" | wc -l) caught by the watchdog (exit 3, step named)," \
    "**$failures other outcomes** (crash, hang, silent NaN: must be 0)"
  echo
  echo "| scene | dt / dt_c | K_S | particles | exit | outcome | wall s | detail |"
  echo "| --- | --- | --- | --- | --- | --- | --- | --- |"
  awk -F, 'NR > 1 { printf "| %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8 }' "$CSV"
} >"$OUT/stability.md"
echo "stability table: $OUT/stability.md ($failures failures)"
[[ $failures == 0 ]]
