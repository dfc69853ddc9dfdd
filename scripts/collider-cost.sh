#!/usr/bin/env bash
# What colliders cost per step on the glass plate at 1M particles (--scale 8; run on a GPU):
# the scene as it is, with 64 fixed spheres pressed into the plate (their lowest point at the top
# layer's particles: each pushes the particles under it), with one 100k-triangle sphere mesh
# pressed into it likewise (its distance grid), and with 8 and 64 free spheres landing on it at
# 1 m/s from that height (a reaction reduced per body per step). Prints the step
# time of each and its excess over the plain scene, and keeps the bench logs and JSON in $OUT.
#   scripts/collider-cost.sh [BINARY] [BACKEND] [SCALE]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/cuda/perifrac}
backend=${2:-cuda}
scale=${3:-8}
out=${OUT:-out}/collider-cost
mkdir -p "$out"
base=scenes/glass_plate_projectile.toml

# A copy of the plate scene with colliders appended (the mesh path made absolute).
variant() {
  local name=$1
  cp "$base" "$out/$name.toml"
  cat >>"$out/$name.toml"
}
# 8 x 8 spheres of r = 15 mm, their lowest point at z = 8.5 mm, just below the top layer's particle
# centres (8.75 mm at scale 1, 9.4 mm at scale 8; the top face is at 10 mm); free ones move down at 1 m/s.
spheres() {
  local extra=$1 n=$2 k=0
  for i in $(seq 0 7); do
    for j in $(seq 0 7); do
      [ $k -ge "$n" ] && return
      printf '[[colliders]]\nshape = "sphere"\nradius = 0.015\ncenter = [%s, %s, 0.0235]\n%s\n' \
        "$(awk -v i="$i" 'BEGIN {print -0.14 + 0.04 * i}')" "$(awk -v j="$j" 'BEGIN {print -0.14 + 0.04 * j}')" "$extra"
      k=$((k + 1))
    done
  done
}
variant plain </dev/null
spheres "" 64 | variant fixed64
spheres $'density = 7800.0\nvelocity = [0.0, 0.0, -1.0]' 8 | variant free8
spheres $'density = 7800.0\nvelocity = [0.0, 0.0, -1.0]' 64 | variant free64
# A sphere of r = 0.1 m meshed at 1.5 mm (about 100k triangles), pressed in like the spheres.
cat >"$out/sphere-body.toml" <<TOML
[materials.m]
model = "bond_based"
density = 1000.0
bulk_modulus = 1e9
strain_limit = 0.01
[[bodies]]
name = "ball"
shape = "sphere"
radius = 0.1
spacing = 0.01
material = "m"
TOML
"$bin" shapes "$out/sphere-body.toml" --edge 0.0015 --out "$out/mesh" >"$out/shapes.log"
triangles=$(grep -c '^f ' "$out/mesh/ball.obj")
printf '[[colliders]]\nshape = "mesh"\nmesh = "%s"\ncenter = [0.0, 0.0, 0.1085]\n' "$(cd "$out/mesh" && pwd)/ball.obj" |
  variant mesh100k

printf '%-10s %12s %12s %10s  %s\n' variant "step [ms]" "wall [ms]" "excess" "bodyforces [ms]"
for name in plain fixed64 mesh100k free8 free64; do
  "$bin" bench --scene "$out/$name.toml" --scale "$scale" --backend "$backend" --steps 500 --warmup 50 \
    --out "$out/bench" >"$out/$name.log" 2>&1 || { echo "$name: bench failed (see $out/$name.log)" >&2; exit 1; }
  step=$(awk '/^step \(all kernels\)/ {print $5}' "$out/$name.log")
  wall=$(awk '/^wall/ {printf "%.4f", $2 / $5 * 1000}' "$out/$name.log")
  body=$(awk '/^pd\/bodyforces/ {print $3}' "$out/$name.log")
  [ "$name" = plain ] && plain_wall=$wall
  printf '%-10s %12s %12s %9.1f%%  %s\n' "$name" "$step" "$wall" "$(awk -v a="$wall" -v b="$plain_wall" 'BEGIN {print 100 * (a / b - 1)}')" "$body"
done
echo "mesh: $triangles triangles; $(grep -h '^device\|^bench' "$out/plain.log" | head -1)"
