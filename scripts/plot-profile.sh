#!/usr/bin/env bash
# Plots a `perifrac profile` timeline (ms per step of each kernel over the run) as a PNG with
# gnuplot (Debian gnuplot-nox, installed with apt-get if missing).
#   scripts/plot-profile.sh RUN_timeline.csv [OUT.png]
set -euo pipefail
csv=$1 png=${2:-${1%.csv}.png}
if ! command -v gnuplot >/dev/null; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get install -y -qq gnuplot-nox >/dev/null || { echo "plot-profile: needs gnuplot" >&2; exit 1; }
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# One data file per kernel: step (middle of the chunk), ms per step.
grep -v '^#' "$csv" | tail -n +2 | awk -F, -v dir="$tmp" '{print ($1 + $2) / 2, $4 > (dir "/" $3 ".dat")}'
plots=""
for f in "$tmp"/*.dat; do
  k=$(basename "$f" .dat)
  plots+="${plots:+, }'$f' using 1:2 with lines lw 2 title '$k'"
done
gnuplot <<GP
set terminal pngcairo size 1000,600 noenhanced
set output '$png'
set title "$(head -n 1 "$csv" | sed 's/^# //; s/"//g')" font ",10"
set xlabel 'step'
set ylabel 'ms per step'
set key outside right
set grid
plot $plots
GP
echo "plot       $png"
