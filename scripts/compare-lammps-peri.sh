#!/usr/bin/env bash
# Side by side with LAMMPS (Debian packages lammps and lammps-examples): its examples/peri PMB
# indenter input, run as written (thermo every 100 steps and the damage at the end added), and
# scenes/validation/lammps_peri_pmb.toml, the same problem as a perifrac scene. Prints the
# particle counts, the kinetic and bond energy every 100 steps (LAMMPS's, per unit volume under
# atom_style peri, times the atoms' volume) and the damage at the end.
#   scripts/compare-lammps-peri.sh [BINARY]
set -euo pipefail
cd "$(dirname "$0")/.."
bin=${1:-build/cpu/perifrac}
out=${OUT:-out}/compare-lammps-peri
example=/usr/share/lammps/examples/peri/in.peri.pmb
command -v lmp >/dev/null || { echo "compare-lammps-peri: no lmp (Debian: apt-get install lammps)" >&2; exit 1; }
[ -f "$example" ] || { echo "compare-lammps-peri: no $example (Debian: apt-get install lammps-examples)" >&2; exit 1; }
rm -rf "$out"
mkdir -p "$out"
sed -e 's|^thermo .*|thermo 100\nthermo_style custom step ke pe etotal|' \
  -e 's|^#dump            1 all custom 100 dump.peri id type x y z c_1|dump 1 all custom 1000 dump.peri id x y z c_1\ndump_modify 1 sort id|' \
  "$example" >"$out/in.peri.pmb"
(cd "$out" && lmp -in in.peri.pmb -log lammps.log >/dev/null)
OMP_NUM_THREADS=${OMP_NUM_THREADS:-2} "$bin" run --overwrite scenes/validation/lammps_peri_pmb.toml --out "$out/perifrac" >"$out/perifrac.log" 2>&1
python3 - "$out" <<'PY'
import csv, struct, sys
out = sys.argv[1]
# LAMMPS: thermo rows "step ke pe etotal", the atom count and the damage of the last dump.
rows, atoms, lines = {}, None, open(f"{out}/lammps.log").read().splitlines()
for i, line in enumerate(lines):
    w = line.split()
    if line.startswith("Created") and "atoms" in line: atoms = int(w[1])
    if len(w) == 4 and w[0].isdigit():
        try: rows[int(w[0])] = [float(x) for x in w[1:]]
        except ValueError: pass
dump = open(f"{out}/dump.peri").read().splitlines()
start = max(i for i, l in enumerate(dump) if l.startswith("ITEM: ATOMS")) + 1  # the last snapshot
damage_lmp = [float(l.split()[4]) for l in dump[start:start + atoms]]
# perifrac: energy.csv per frame (100 steps) and the last frame's damage (.pfr, docs/output-formats.md).
volume = 1.25e-10  # every atom's (set group all volume)
ours = {int(r["step"]): r for r in csv.DictReader(open(f"{out}/perifrac/energy.csv"))}
def pfr_damage(path):
    b = open(path, "rb").read()
    n = struct.unpack_from("<Q", b, 16)[0]
    arrays, off = struct.unpack_from("<I", b, 48)[0], 52
    for _ in range(arrays):
        name = b[off:off + 16].rstrip(b"\0").decode(); _, comps = struct.unpack_from("<II", b, off + 16)
        off += 24
        if name == "damage": return list(struct.unpack_from(f"<{n}f", b, off))
        off += 4 * n * comps
damage_ours = pfr_damage(f"{out}/perifrac/frame_00010.pfr")
print(f"particles       LAMMPS {atoms}   perifrac {len(damage_ours)}")
print(f"{'step':>6} {'LAMMPS ke':>12} {'LAMMPS pe':>12} {'perifrac ke':>12} {'perifrac pe':>12}   [J]")
for step in sorted(rows):
    if step == 0 or step not in ours: continue
    ke, pe = (volume * x for x in rows[step][:2])  # LAMMPS's peri energies are per unit volume
    print(f"{step:>6} {ke:12.4g} {pe:12.4g} {float(ours[step]['kinetic']):12.4g} {float(ours[step]['strain']):12.4g}")
mean = lambda v: sum(v) / len(v)
print(f"mean damage at step 1000: LAMMPS {mean(damage_lmp):.4f}   perifrac {mean(damage_ours):.4f}")
print(f"particles with damage > 0.5: LAMMPS {sum(d > 0.5 for d in damage_lmp)}   perifrac {sum(d > 0.5 for d in damage_ours)}")
PY
