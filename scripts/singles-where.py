#!/usr/bin/env python3
"""Where a run's single-particle pieces come from (issue 31): the particles of a frame's
one-particle fragments counted by their rest distance from a point, in bands.

  scripts/singles-where.py RUN_DIR [--frame N] [--center X,Y,Z] [--band METRES] [--bands K]

Reads RUN_DIR/points_00000.ply (rest positions: frame 0 is the rest state) and the frame's
points_NNNNN.ply (fragment ids; default the last frame written). Prints per band the particles,
those in single-particle fragments, and the band's share of all singles, so a [[shards]] zone
can be sized to where the grit forms. Standard library only.
"""
import argparse
import glob
import os
import struct
import sys


def read_points(path):
    """Positions and fragment ids of a points PLY (binary little endian, perifrac's layout)."""
    with open(path, "rb") as f:
        props, count = [], 0
        if f.readline().strip() != b"ply":
            sys.exit(f"singles-where: {path} is not a PLY file")
        while True:
            line = f.readline()
            if not line:
                sys.exit(f"singles-where: {path} ends inside its header")
            words = line.split()
            if words[:2] == [b"element", b"vertex"]:
                count = int(words[2])
            elif words[:1] == [b"property"]:
                props.append((words[1].decode(), words[2].decode()))
            elif words[:1] == [b"end_header"]:
                break
        codes = {"float": "f", "int": "i", "uchar": "B", "double": "d", "uint": "I"}
        fmt = "<" + "".join(codes[t] for t, _ in props)
        names = [n for _, n in props]
        size = struct.calcsize(fmt)
        data = f.read(size * count)
        if len(data) != size * count:
            sys.exit(f"singles-where: {path} holds fewer than its {count} points")
    ix, iy, iz, ic = (names.index(k) for k in ("x", "y", "z", "component"))
    pos, comp = [], []
    for row in struct.iter_unpack(fmt, data):
        pos.append((row[ix], row[iy], row[iz]))
        comp.append(row[ic])
    return pos, comp


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run")
    ap.add_argument("--frame", type=int)
    ap.add_argument("--center", default="0,0,0")
    ap.add_argument("--band", type=float, default=0.01, help="band width [m]")
    ap.add_argument("--bands", type=int, default=16)
    a = ap.parse_args()
    frames = sorted(glob.glob(os.path.join(a.run, "points_*.ply")))
    if not frames:
        sys.exit(f"singles-where: no points_*.ply in {a.run}")
    last = os.path.join(a.run, f"points_{a.frame:05d}.ply") if a.frame is not None else frames[-1]
    rest, _ = read_points(os.path.join(a.run, "points_00000.ply"))
    _, comp = read_points(last)
    if len(rest) != len(comp):
        sys.exit("singles-where: frame 0 and the frame hold different particle counts")
    size = {}
    for c in comp:
        size[c] = size.get(c, 0) + 1
    c0 = [float(v) for v in a.center.split(",")]
    total = [0] * (a.bands + 1)
    single = [0] * (a.bands + 1)
    for p, c in zip(rest, comp):
        r = sum((p[k] - c0[k]) ** 2 for k in range(3)) ** 0.5
        b = min(int(r / a.band), a.bands)
        total[b] += 1
        single[b] += size[c] == 1
    n_single = sum(single)
    print(f"# {os.path.basename(last)}: {len(comp)} particles, {n_single} in single-particle pieces "
          f"({100.0 * n_single / len(comp):.2f}%); rest distance from {a.center}")
    print(f"{'band [m]':>17} {'particles':>10} {'singles':>9} {'of band':>8} {'of singles':>10} {'cumulative':>10}")
    acc = 0
    for b in range(a.bands + 1):
        if total[b] == 0:
            continue
        acc += single[b]
        hi = f"{(b + 1) * a.band:.3f}" if b < a.bands else "up"
        print(f"{b * a.band:8.3f}-{hi:>8} {total[b]:10d} {single[b]:9d} {100.0 * single[b] / total[b]:7.1f}% "
              f"{100.0 * single[b] / max(n_single, 1):9.1f}% {100.0 * acc / max(n_single, 1):9.1f}%")


if __name__ == "__main__":
    main()
