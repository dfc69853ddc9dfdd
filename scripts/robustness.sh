#!/usr/bin/env bash
# The robustness table (docs/robustness.md): hostile inputs and situations, by class, each run
# through the perifrac binary and held to what it must do: the exit code, one "error:" line naming
# the key or option (or the warning, or the files left), and no NaN or inf in any file written.
#   scripts/robustness.sh BIN                 prints the table; exit 1 when a case fails
#   scripts/robustness.sh BIN --check FILE    also exit 1 when FILE's table differs (CI: the doc
#                                             stays what the binary does)
#   scripts/robustness.sh BIN --write FILE    writes the table into FILE
# Each case takes well under a second on one core, but for the SIGTERM one.
set -uo pipefail
cd "$(dirname "$0")/.."

[[ $# -ge 1 ]] || { sed -n '2,10p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
BIN=$(realpath "$1"); shift
MODE="" FILE=""
if [[ $# -eq 2 && ( $1 == --check || $1 == --write ) ]]; then MODE=$1 FILE=$2; fi
[[ -x $BIN ]] || { echo "error: no perifrac binary at '$BIN'" >&2; exit 2; }
export OMP_NUM_THREADS=1
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
cd "$W" || exit 2

# ---- Scenes -----------------------------------------------------------------------------------
scene() {  # NAME [EXTRA TOML]: a small glass block (about 100 particles, 2 frames of 20 steps)
  {
    printf '[simulation]\nsteps_per_frame = 20\nframes = 2\n'
    printf '[materials.glass]\ndensity = 2200.0\nbulk_modulus = 32.81e9\nstrain_limit = 5e-4\n'
    printf '[[bodies]]\nname = "block"\nmaterial = "glass"\nsize = [0.02, 0.01, 0.01]\nspacing = 0.002\n'
    printf 'velocity = [1.0, 0.0, 0.0]\n'
    printf '%b' "${2:-}"
  } >"$1"
}
scene s.toml
scene t.toml '# another scene\n'
scene long.toml '[[bodies]]\nname = "far"\nmaterial = "glass"\ncenter = [1, 0, 0]\nsize = [0.04, 0.02, 0.02]\nspacing = 0.002\n'
scene drop.toml '[world]\nfloor = true\nfloor_height = -0.003\n'

# ---- Cases ------------------------------------------------------------------------------------
rows=()
failures=0
# case CLASS "CASE" EXIT "PATTERN" COMMAND...: runs COMMAND (output in out.txt), then checks the
# exit code, the pattern (grep -E) in the output, an exit 2's one "error:" line, and the files.
case_() {
  local class=$1 what=$2 want=$3 pattern=$4 code why=""
  shift 4
  "$@" >out.txt 2>&1
  code=$?
  [[ $code == "$want" ]] || why="exit $code, expected $want"
  [[ -z $why && -n $pattern ]] && ! grep -qE -- "$pattern" out.txt && why="no '$pattern' in the output"
  if [[ -z $why && $want == 2 ]]; then
    [[ $(grep -c '^error: ' out.txt) == 1 ]] || why="not one 'error:' line"
  fi
  if [[ -z $why ]] && grep -qiwE 'nan|-?inf' out.txt; then why="nan or inf in the message"; fi
  if [[ -z $why ]] && ! finite_files; then why="a file holds nan or inf"; fi
  if [[ -z $why && -n ${POST:-} ]] && ! eval "$POST"; then why="check failed: $POST"; fi
  local expected="exit $want${pattern:+, \`${pattern//|/\\|}\`}"
  if [[ -z $why ]]; then
    rows+=("| $class | $what | $expected | pass |")
  else
    rows+=("| $class | $what | $expected | **FAIL**: $why |")
    failures=$((failures + 1))
    sed 's/^/    /' out.txt | head -5 >&2
  fi
  POST=""
}
# No NaN or inf token in the text files written under the working folder.
finite_files() {
  ! find . -type f \( -name '*.csv' -o -name '*.obj' -o -name '*.vtu' -o -name '*.pvd' \) -print0 |
    xargs -0 -r grep -liwE 'nan|-?inf' | grep -q .
}
fresh() { rm -rf "$@"; }
P=(run --backend cpu)

# Run folders
fresh o
"$BIN" "${P[@]}" s.toml --frames 4 --out o >/dev/null 2>&1
case_ "run folder" "a second run into a used folder" 2 "--overwrite" "$BIN" "${P[@]}" s.toml --out o
POST='[[ ! -e o/frame_00003.pfr && ! -e o/frame_00004.pfr ]]'
case_ "run folder" "--overwrite of a longer run: no stale frame" 0 "removed the [0-9]+ files" "$BIN" "${P[@]}" s.toml --frames 2 --overwrite --out o
fresh busy
"$BIN" "${P[@]}" long.toml --frames 100000 --out busy >/dev/null 2>&1 &
busy=$!
for _ in $(seq 100); do [[ -e busy/frame_00000.pfr ]] && break; sleep 0.05; done
case_ "run folder" "two runs in one folder at once" 2 "in use by a running perifrac" "$BIN" "${P[@]}" s.toml --overwrite --out busy
kill -9 $busy 2>/dev/null; wait $busy 2>/dev/null
fresh a b
"$BIN" "${P[@]}" s.toml --checkpoint-every 2 --out a >/dev/null 2>&1
"$BIN" "${P[@]}" t.toml --checkpoint-every 2 --out b >/dev/null 2>&1
cp a/checkpoint.pck b/checkpoint.pck
case_ "run folder" "a checkpoint copied from another run's folder" 2 "copied from another run's folder" "$BIN" run --resume b --frames 3
fresh old && mkdir old && : >old/frame_00000.pfr
case_ "run folder" "outputs of a run without a manifest" 2 "kept no run.manifest" "$BIN" "${P[@]}" s.toml --overwrite --out old

# Bounded inputs
fresh o
case_ "bounded input" "scene file /dev/zero" 2 "not a regular file" "$BIN" "${P[@]}" /dev/zero --out o
ln -sf /dev/urandom random.toml
case_ "bounded input" "scene file a symlink to /dev/urandom" 2 "not a regular file" "$BIN" "${P[@]}" random.toml --out o
ln -sf /dev/zero zero.obj
scene mesh.toml '[[bodies]]\nshape = "mesh"\nmesh = "zero.obj"\nmaterial = "glass"\nspacing = 0.002\n'
case_ "bounded input" "mesh file a symlink to /dev/zero" 2 "not a regular file" "$BIN" "${P[@]}" mesh.toml --out o
head -c 2000000 /dev/zero | tr '\0' '#' >big.toml
case_ "bounded input" "scene over PERIFRAC_MAX_INPUT_MB" 2 "larger than the input limit" env PERIFRAC_MAX_INPUT_MB=1 "$BIN" "${P[@]}" big.toml --out o
case_ "bounded input" "render --environment /dev/zero" 2 "--environment '/dev/zero': not a regular file" "$BIN" render o --environment /dev/zero
case_ "bounded input" "PERIFRAC_MAX_INPUT_MB=lots" 2 "PERIFRAC_MAX_INPUT_MB" env PERIFRAC_MAX_INPUT_MB=lots "$BIN" "${P[@]}" s.toml --out o
case_ "bounded input" "PERIFRAC_HOST_MEMORY_MB=-5" 2 "PERIFRAC_HOST_MEMORY_MB" env PERIFRAC_HOST_MEMORY_MB=-5 "$BIN" "${P[@]}" s.toml --out o

# Finite output
for set in "materials.glass.density=1e308|materials.glass.density" "materials.glass.density=1e-308|materials.glass.density" \
  "bodies[0].velocity=[0,0,1e300]|bodies\[0\].velocity" "bodies[0].velocity=[1e30,0,0]|bodies\[0\].velocity" \
  "materials.glass.bulk_modulus=1e300|materials.glass:"; do
  fresh o
  POST='[[ ! -e o ]]'
  case_ "finite output" "--set ${set%%|*}: refused before any file" 2 "${set#*|}" "$BIN" "${P[@]}" s.toml --set "${set%%|*}" --out o
done
fresh o
scene blow.toml '[world]\nfloor = true\nfloor_height = -0.003\n'  # (particles of 1e-37 kg pushed by the floor)
sed -i 's/^density = 2200.0/density = 1e-29/' blow.toml
case_ "finite output" "overflow to infinity: blow-up caught, files finite" 3 "numerical blow-up: .* by step 20" "$BIN" "${P[@]}" blow.toml --allow-unstable-dt --out o
fresh o
dtc=$("$BIN" "${P[@]}" "$OLDPWD/scenes/validation/stress_drop.toml" --frames 0 --out probe 2>/dev/null | sed -n 's/.*dt_c \([0-9.e+-]*\) s.*/\1/p' | sort -g | head -1)
case_ "finite output" "--allow-unstable-dt at 2 dt_c: stops on energy growth" 3 "stops at 0.1" "$BIN" "${P[@]}" "$OLDPWD/scenes/validation/stress_drop.toml" --set "simulation.dt=$(awk -v a="$dtc" 'BEGIN { printf "%.6e", 2 * a }')" --allow-unstable-dt --out o
fresh o
case_ "finite output" "bench past the stable step: refused as run refuses it" 2 "simulation.dt: dt = .* exceeds the stable time step" "$BIN" bench --scene s.toml --set simulation.dt=1e-3 --backend cpu --steps 1 --out o

# Resume
fresh r
"$BIN" "${P[@]}" s.toml --checkpoint-every 1 --out r >/dev/null 2>&1
case_ "resume" "--scale given to a resume" 2 "--scale 0.5 differs" "$BIN" run --resume r --scale 0.5
case_ "resume" "--overwrite with --resume" 2 "excludes" "$BIN" run --resume r --overwrite
case_ "resume" "from another working directory" 0 "resume     from frame 2" env -C / "$BIN" run --resume "$PWD/r" --frames 3
cp r/checkpoint.pck saved.pck
head -c 1000 saved.pck >r/checkpoint.pck
case_ "resume" "a truncated checkpoint" 2 "checksum mismatch|truncated" "$BIN" run --resume r --frames 4
fresh r2
"$BIN" "${P[@]}" s.toml --frames 4 --checkpoint-every 2 --out r2 >/dev/null 2>&1 && cp r2/checkpoint.pck r2-4.pck
"$BIN" "${P[@]}" s.toml --frames 2 --checkpoint-every 2 --out r2b >/dev/null 2>&1 && cp r2b/checkpoint.pck r2/checkpoint.pck
POST='[[ -e r2/frame_00004.pfr ]]'
case_ "resume" "ending before frames already written: refused, nothing removed" 2 "frames 4 to 4 would be removed" "$BIN" run --resume r2 --frames 3
fresh k
"$BIN" "${P[@]}" s.toml --frames 1 --steps-per-frame 200000 --out k >out-k.txt 2>&1 &
run=$!
for _ in $(seq 200); do [[ -e k/frame_00000.pfr ]] && break; sleep 0.05; done
sleep 0.3
kill -TERM $run
t0=$(date +%s.%N)
wait $run
code=$?
stop=$(awk -v a="$t0" -v b="$(date +%s.%N)" 'BEGIN { printf "%.2f", b - a }')
POST="awk -v s=$stop 'BEGIN { exit !(s < 1) }'"
case_ "resume" "SIGTERM inside a 200,000-step frame: stops within 1 s" 130 "interrupted in frame 1" sh -c "cat out-k.txt; exit $code"

# The command line
fresh o
case_ "command line" "--frames 99999999999999999999" 2 "--frames" "$BIN" "${P[@]}" s.toml --frames 99999999999999999999 --out o
POST='[[ -e o/frame_00000.pfr && ! -e o/frame_00001.pfr ]]'
case_ "command line" "--frames 0: the set-up and frame 0" 0 "" "$BIN" "${P[@]}" s.toml --frames 0 --out o
scene zero.toml
sed -i 's/^frames = 2/frames = 0/' zero.toml
case_ "command line" "frames = 0 in the scene: the same" 0 "" "$BIN" "${P[@]}" zero.toml --out z
case_ "command line" "--set with a line break" 2 "--set" "$BIN" "${P[@]}" s.toml --set $'simulation.frames=3\nmaterials.glass.density=1' --out o3
case_ "command line" "--set with an index past 2^64" 2 "bodies\[" "$BIN" "${P[@]}" s.toml --set 'bodies[99999999999999999999].spacing=1' --out o3
case_ "command line" "an unknown option" 2 "--no-such-option" "$BIN" "${P[@]}" s.toml --no-such-option
case_ "command line" "--backend gpu" 2 "--backend" "$BIN" run s.toml --backend gpu
case_ "command line" "PERIFRAC_BOND_THREADS=7" 2 "PERIFRAC_BOND_THREADS='7'" env PERIFRAC_BOND_THREADS=7 "$BIN" "${P[@]}" s.toml --out o4
case_ "command line" "PERIFRAC_STEP_GRAPHS=yes" 2 "PERIFRAC_STEP_GRAPHS='yes'" env PERIFRAC_STEP_GRAPHS=yes "$BIN" "${P[@]}" s.toml --out o4
case_ "command line" "PERIFRAC_BALANCE_WINDOW=-1" 2 "PERIFRAC_BALANCE_WINDOW='-1'" env PERIFRAC_BALANCE_WINDOW=-1 "$BIN" "${P[@]}" s.toml --out o4
case_ "command line" "PERIFRAC_TEAM_BLOCK=64" 2 "PERIFRAC_TEAM_BLOCK='64'" env PERIFRAC_TEAM_BLOCK=64 "$BIN" "${P[@]}" s.toml --out o4
case_ "command line" "PERIFRAC_OVERLAP_LAUNCHES=no" 2 "PERIFRAC_OVERLAP_LAUNCHES='no'" env PERIFRAC_OVERLAP_LAUNCHES=no "$BIN" "${P[@]}" s.toml --out o4
case_ "command line" "an argument with a line break" 2 "^error: .*\?" "$BIN" "${P[@]}" s.toml $'--out\nx' extra
sed 's/^steps_per_frame = 20/dt = 5e-324\nsteps_per_frame = 20/' s.toml >tiny-dt.toml
case_ "command line" "dt = 5e-324" 2 "simulation.dt" "$BIN" "${P[@]}" tiny-dt.toml --out o2
scene shards.toml '[[shards]]\nsize = 1e-7\n'
case_ "command line" "[[shards]] cells far smaller than the particles" 2 "shards\[0\]\.size" "$BIN" "${P[@]}" shards.toml --out o5
scene pattern.toml '[[shards]]\nsize = 0.01\npattern = "no-such-run"\n'
case_ "command line" "[[shards]] pattern: a folder without a checkpoint" 2 "shards\[0\]\.pattern" "$BIN" "${P[@]}" pattern.toml --out o6
scene dust.toml '[[shards]]\nsize = 0.01\ndust_hold = 2\n'
case_ "command line" "surface_correction neither a boolean nor \"ghosts\"" 2 "materials\.glass\.surface_correction" \
  "$BIN" "${P[@]}" s.toml --set 'materials.glass.surface_correction="faces"' --out o9
case_ "command line" "[[shards]] dust_hold without a pattern" 2 "shards\[0\]\.dust_hold" "$BIN" "${P[@]}" dust.toml --out o7
"$BIN" "${P[@]}" s.toml --out o8 >/dev/null 2>&1 && rm -f o8/crack_mesh_*
case_ "run folder" "render --surface mesh of a run whose crack meshes are gone" 4 "o8/crack_mesh_00000.ply': missing, though the run wrote it" "$BIN" render o8 --surface mesh --width 32 --height 32
mkdir -p not-a-run
case_ "command line" "render of a folder that holds no run" 2 "holds no complete frame_\*.pfr" "$BIN" render not-a-run
case_ "command line" "render --out naming a file" 2 "--out 's.toml' is a file, not a folder" "$BIN" render o8 --out s.toml
case_ "command line" "render --eye beyond 1e9 m" 2 "eye 1e\+30,1e\+30,1e\+30 is too far out" "$BIN" render o8 --eye 1e30,1e30,1e30
case_ "command line" "render --eye straight above the target" 0 "rendered   3 frames" "$BIN" render o8 --eye 0,1,0 --look-at 0,0,0 --width 32 --height 32 --no-movie
case_ "command line" "render --ior nan" 2 "--ior: value out of range" "$BIN" render o8 --ior nan
{ printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n'; head -c 16 /dev/zero | tr '\0' '\200'; } >cut.hdr
case_ "bounded input" "render --environment of a truncated .hdr" 2 "cut.hdr': truncated: the file ends before its 4 x 2 texels do" "$BIN" render o8 --environment cut.hdr
case_ "command line" "info into a full disk (/dev/full)" 4 "cannot write the standard output" sh -c "'$BIN' info >/dev/full"
# A killed run's last frame (past the manifest's frames written), and a frame file the run wrote gone.
cp -r o8 o11 && sed -i 's/^frames_written 2$/frames_written 1/' o11/run.manifest
case_ "run folder" "render of a killed run's unfinished frame: left out" 0 "frame 2 left out: its files are incomplete" "$BIN" render o11 --width 32 --height 32 --no-movie
cp -r o8 o12 && rm o12/frame_00001.pfr
case_ "run folder" "render of a run whose frame file is gone" 4 "o12/frame_00001.pfr': missing, though the run wrote it" "$BIN" render o12 --no-movie
case_ "run folder" "compare with a frame in one folder only" 1 "MISSING \(only in o8\)" "$BIN" compare o8 o11
case_ "command line" "--out naming a file" 2 "is a file, not a folder" "$BIN" "${P[@]}" s.toml --out s.toml
case_ "command line" "an unknown command" 2 "unknown command 'simulate'" "$BIN" simulate s.toml

# Limits: what would hang, run for nothing or overflow a count
mkdir -p slow-tetgen && printf '#!/bin/sh\nexec sleep 60\n' >slow-tetgen/tetgen && chmod +x slow-tetgen/tetgen
scene shell.toml '[[bodies]]\nname = "ball"\nmaterial = "glass"\nshape = "sphere"\nradius = 0.01\ncenter = [0.1, 0, 0]\nspacing = 0.002\nparticles = "shell"\nshell_thickness = 0.012\n'
case_ "limits" "a shell deeper than its sphere: refused before TetGen" 2 "bodies\[1\]\.shell_thickness: .* folds its inner surface over" "$BIN" "${P[@]}" shell.toml --out l7
mkdir -p folder.obj
scene dirmesh.toml '[[bodies]]\nshape = "mesh"\nmesh = "folder.obj"\nmaterial = "glass"\nspacing = 0.002\n'
case_ "bounded input" "a mesh path that is a folder" 2 "is a folder, not a mesh file" "$BIN" "${P[@]}" dirmesh.toml --out o10
printf 'v 0 0 0\nv 0.01 0 0\nv 0 0.01 0\nv 0 0 0.01\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n' >tetra.obj
scene hugemesh.toml '[[bodies]]\nshape = "mesh"\nmesh = "tetra.obj"\nscale = 1e300\nmaterial = "glass"\nspacing = 0.002\n'
case_ "limits" "a mesh scale of 1e300" 2 "bodies\[1\]\.scale: 1e\+300 is out of range" "$BIN" "${P[@]}" hugemesh.toml --out o13
printf 'solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\n' >cut.stl
scene cutmesh.toml '[[bodies]]\nshape = "mesh"\nmesh = "cut.stl"\nmaterial = "glass"\nspacing = 0.002\n'
case_ "bounded input" "an ascii STL cut short" 2 "cut.stl: the file ends before its 'endsolid' line" "$BIN" "${P[@]}" cutmesh.toml --out o14
scene tets.toml '[[bodies]]\nname = "ball"\nmaterial = "glass"\nshape = "sphere"\nradius = 0.01\ncenter = [0.1, 0, 0]\nspacing = 0.004\nparticles = "tets"\n'
case_ "limits" "a TetGen run that does not end: stopped" 2 "was stopped after 1 s" \
  env PATH="$PWD/slow-tetgen:$PATH" PERIFRAC_TETGEN_SECONDS=1 PERIFRAC_TET_CACHE=off "$BIN" "${P[@]}" tets.toml --out l1
case_ "limits" "PERIFRAC_TETGEN_SECONDS=soon" 2 "PERIFRAC_TETGEN_SECONDS='soon'" \
  env PATH="$PWD/slow-tetgen:$PATH" PERIFRAC_TETGEN_SECONDS=soon PERIFRAC_TET_CACHE=off "$BIN" "${P[@]}" tets.toml --out l8
scene stiff.toml '[[colliders]]\nshape = "sphere"\nradius = 0.01\ncenter = [0, 0.2, 0]\nstiffness = 1e300\n'
case_ "limits" "a collider stiffness that leaves no stable step" 2 "colliders: the colliders' contact" "$BIN" "${P[@]}" stiff.toml --out l2
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n' >sheet.obj
scene cell.toml '[[colliders]]\nshape = "mesh"\nmesh = "sheet.obj"\ncenter = [0, 0.2, 0]\ncell = 1e-9\n'
case_ "limits" "a mesh collider's distance grid of 1e27 nodes" 2 "colliders\[0\]\.cell" "$BIN" "${P[@]}" cell.toml --out l3
sed 's/^spacing = 0.002/spacing = 0.002\ncenter = [1e4, 0, 0]/' s.toml >far.toml
case_ "limits" "a body 1e4 m from the origin (float positions)" 2 "bodies\[0\]\.center" "$BIN" "${P[@]}" far.toml --out l4
case_ "limits" "run --checkpoint-minutes nan" 2 "--checkpoint-minutes" "$BIN" "${P[@]}" s.toml --checkpoint-minutes nan --out l5
case_ "limits" "validate --dt-fraction 50" 2 "--dt-fraction" "$BIN" validate --problem wave_bar --dt-fraction 50
case_ "limits" "validate --resolution 100000" 2 "resolution 100000" "$BIN" validate --problem wave_bar --resolution 100000
case_ "limits" "bench-geometry --tet-quality 0.5" 2 "--tet-quality" "$BIN" bench-geometry --tet-quality 0.5
case_ "limits" "run --out '' (an empty folder name)" 2 "--out: an empty name" "$BIN" "${P[@]}" s.toml --out ''
case_ "limits" "validate --csv into /proc: refused before the work" 4 "cannot write '/proc/x.csv'" "$BIN" validate --problem wave_bar --resolution 4 --csv /proc/x.csv
case_ "limits" "bench-geometry --csv into /proc: refused before the work" 4 "cannot write /proc/x.csv" "$BIN" bench-geometry --shape sphere --particles grid --count 1000 --csv /proc/x.csv
scene spin.toml '[[anchors]]\nbox_min = [-1, -1, -1]\nbox_max = [1, 1, 1]\nangular_velocity = [1e30, 0, 0]\n'
case_ "finite output" "an anchor spinning past the speed of light: the anchor named" 2 "anchors\[0\]" "$BIN" "${P[@]}" spin.toml --out l7
scene push.toml '[[projectiles]]\ncenter = [0, 0.1, 0]\nvelocity = [0, -1, 0]\nradius = 0.005\nstrength = 1e300\n'
case_ "finite output" "a projectile strength of 1e300" 2 "projectiles\[0\]\.strength" "$BIN" "${P[@]}" push.toml --out l8
scene hard.toml '[contact]\nenabled = true\nstiffness = 1e300\n'
case_ "finite output" "a contact stiffness of 1e300" 2 "contact\.stiffness" "$BIN" "${P[@]}" hard.toml --out l9
scene speck.toml '[[bodies]]\nname = "speck"\nmaterial = "glass"\nshape = "sphere"\nradius = 0.001\ncenter = [0.1, 0, 0]\nspacing = 0.005\n'
case_ "limits" "a sphere smaller than its spacing" 2 "bodies\[1\]\.spacing: the body holds no particle" "$BIN" "${P[@]}" speck.toml --out l6

# Scene smells
scene anchor.toml '[[anchors]]\nbox_min = [1, 1, 1]\nbox_max = [2, 2, 2]\n'
case_ "scene smell" "an anchor box holding no particle" 0 "warning: anchors\[0\]: its box holds no particle" "$BIN" "${P[@]}" anchor.toml --frames 0 --out s1
scene twins.toml '[[bodies]]\nname = "block"\nmaterial = "glass"\ncenter = [0.1, 0, 0]\nsize = [0.01, 0.01, 0.01]\nspacing = 0.002\n'
case_ "scene smell" "two bodies of one name" 0 "both named 'block'" "$BIN" "${P[@]}" twins.toml --frames 0 --out s2
case_ "scene smell" "a body below the floor" 0 "start below the floor" "$BIN" "${P[@]}" drop.toml --frames 0 --out s3
scene overlap.toml '[[bodies]]\nname = "lid"\nmaterial = "glass"\ncenter = [0.004, 0, 0]\nsize = [0.02, 0.01, 0.01]\nspacing = 0.002\n'
case_ "scene smell" "overlapping bodies" 0 "bodies 'block' and 'lid' overlap" "$BIN" "${P[@]}" overlap.toml --frames 0 --out s4
case_ "scene smell" "a collider started inside the body: the blow-up names it" 3 "192 particles started inside or pressed into colliders" "$BIN" "${P[@]}" s.toml --set 'simulation.dt="auto"' --set 'colliders[0].shape="sphere"' --set 'colliders[0].radius=0.008' --set 'colliders[0].center=[0,0,0]' --set 'colliders[0].stiffness=1e13' --out s6
scene region.toml '[[regions]]\nbox_min = [1, 1, 1]\nbox_max = [2, 2, 2]\nstrain_limit = 0.01\n'
case_ "scene smell" "a region holding no particle" 0 "warning: regions\[0\]: it holds no particle" "$BIN" "${P[@]}" region.toml --frames 0 --out s5

# Set-ups that ran away: out of bounds, out of memory or hung before they were refused
scene walk.toml '[[cracks]]\nshape = "random_walk"\nstart = [0, 0, 0]\nextrude = [0, 1, 0]\nstep_length = 1e30\n'
case_ "limits" "a crack walk of 1e30 m steps: set up at once" 0 "frame 0" timeout 60 "$BIN" "${P[@]}" walk.toml --frames 0 --out q1
scene quad.toml '[[cracks]]\ncorners = [[0, -1, -1], [0, 1, -1], [1, 1, 1], [0, -1, 1]]\n'
case_ "limits" "a quad crack that is not planar" 2 "cracks\[0\]\.corners: not planar" "$BIN" "${P[@]}" quad.toml --out q2
case_ "limits" "gravity of 1e20 m/s^2" 2 "world\.gravity: an acceleration of 1e\+20" "$BIN" "${P[@]}" s.toml --set 'world.gravity=[0,-1e20,0]' --out q3
case_ "limits" "an anchor path faster than light" 2 "anchors\[0\]\.path: keyframes 0 to 1" "$BIN" "${P[@]}" anchor.toml --set 'anchors[0].path=[[0,0,0,0],[1e-12,1e3,0,0]]' --out q4
sed 's/^strain_limit = 5e-4/fracture_energy = 1e12/' s.toml >energy.toml
case_ "limits" "a fracture energy giving a stretch above 1" 2 "materials\.glass\.fracture_energy: .* critical stretch" "$BIN" "${P[@]}" energy.toml --out q5
case_ "limits" "--scale leaving a box less than half a spacing thick" 2 "--scale: at this scale the spacing" "$BIN" "${P[@]}" s.toml --scale 1e-6 --out q6
case_ "limits" "profile --timeline 1 over 1e8 steps" 2 "--timeline 1: 100000000 points" "$BIN" profile s.toml --backend cpu --steps 100000000 --timeline 1 --out q7
case_ "limits" "bench --lattice past the memory" 2 "--lattice 400 is 64000000 particles" env PERIFRAC_HOST_MEMORY_MB=100 "$BIN" bench --lattice 400 --backend cpu
case_ "command line" "bench-geometry at a spacing past the shape" 2 "the sphere holds no particle at a spacing of 100 m" "$BIN" bench-geometry --shape sphere --particles grid --spacing 100
case_ "command line" "bench --scene with --lattice" 2 "--scene excludes --lattice" "$BIN" bench --scene s.toml --lattice 10
case_ "command line" "a body name with a '/'" 2 "bodies\[0\]\.name: '\.\./x'" "$BIN" shapes s.toml --set 'bodies[0].name="../x"' --out q8

# ---- Table ------------------------------------------------------------------------------------
table() {
  echo "| class | case | expected | result |"
  echo "| --- | --- | --- | --- |"
  printf '%s\n' "${rows[@]}"
  echo
  echo "${#rows[@]} cases, $failures failed."
}
table >table.md
cd "$OLDPWD" || exit 2
cat "$W/table.md"
status=0
[[ $failures -eq 0 ]] || status=1
if [[ $MODE == --write ]]; then
  { sed '/^<!-- table -->$/q' "$FILE"; cat "$W/table.md"; } >"$FILE.tmp" && mv "$FILE.tmp" "$FILE"
elif [[ $MODE == --check ]]; then
  if ! diff <(sed '1,/^<!-- table -->$/d' "$FILE") "$W/table.md" >/dev/null; then
    echo "robustness: $FILE does not hold this table: run scripts/robustness.sh BIN --write $FILE" >&2
    status=1
  fi
fi
exit $status
