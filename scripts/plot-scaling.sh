#!/usr/bin/env bash
# Plots the parallel efficiency against the number of GPUs from a table that
# scripts/mpi-scaling.sh printed (rows: run GPUs scale particles bond-upd/s efficiency ...):
# strong scaling per problem size and weak scaling, against the ideal and the issue's targets
# (weak 90%, strong 75% at 8 GPUs). gnuplot (Debian gnuplot-nox) is installed if missing.
#   [TITLE=...] scripts/plot-scaling.sh TABLE.txt [OUT.png]   (title: the table's first line)
set -euo pipefail
table=$1 png=${2:-bench/scaling.png}
if ! command -v gnuplot >/dev/null; then
  sudo=""; [ "$(id -u)" -eq 0 ] || sudo=sudo
  $sudo apt-get install -y -qq gnuplot-nox >/dev/null || { echo "plot-scaling: needs gnuplot" >&2; exit 1; }
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# One data file per series (GPUs, efficiency in %): strong-<particles>, weak.
awk -v dir="$tmp" '
  $1 == "strong" || $1 == "weak" {
    eff = $6; sub("%", "", eff); if (eff !~ /^[0-9.]+$/) next
    name = $1 == "weak" ? "weak" : "strong-" $4
    print $2, eff >> (dir "/" name ".dat")
  }' "$table"
ls "$tmp"/*.dat >/dev/null 2>&1 || { echo "plot-scaling: no strong or weak rows in '$table'" >&2; exit 2; }
title=${TITLE:-$(head -n 1 "$table" | sed 's/^# *//; s/"//g' | cut -c1-110)}
plots=()
for f in "$tmp"/*.dat; do
  name=$(basename "$f" .dat)
  label=${name/strong-/strong, }
  [[ $name == strong-* ]] && label="$label particles"
  [[ $name == weak ]] && label="weak (the particles grow with the GPUs)"
  plots+=("'$f' using 1:2 with linespoints lw 2 pt 7 title '$label'")
done
plots+=("100 with lines dt 2 lc rgb 'gray' title 'ideal'")
plots+=("'-' using 1:2 with points pt 6 ps 2 lc rgb 'red' title 'targets at 8 GPUs (weak 90%, strong 75%)'")
{
  echo "set terminal pngcairo size 960,600 font ',11'"
  echo "set output '$png'"
  echo "set title \"$title\" font ',10'"
  echo "set xlabel 'GPUs'; set ylabel 'parallel efficiency [%]'"
  echo "set logscale x 2; set xrange [0.8:10]; set yrange [0:110]; set key bottom left; set grid"
  echo "plot $(IFS=,; echo "${plots[*]}")"
  echo "8 90"; echo "8 75"; echo "e"
} | gnuplot
echo "plot-scaling: $png"
