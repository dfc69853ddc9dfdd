#!/usr/bin/env python3
"""Where TetGen's Steiner points on the surface's segments come from (issue 27's first run).

Reads the input perifrac hands TetGen (in.smesh, and in.a.node where points are inserted; keep it
with `TETGEN_KEEP_INPUT=DIR scripts/tetgen-alone.sh`), counts the triangles' edges that an input
vertex encroaches (strictly inside the edge's diametral sphere, which makes TetGen split the
edge) and the obtuse triangles, and with --flip DIR writes a copy whose encroached edges are
flipped where the flip keeps the surface's orientation and ends encroached by nothing. With
--tetgen SWITCHES runs `tetgen SWITCHES` with V (stage times and counts) on the input, and on
the flipped copy where one was written, and prints its counts of Steiner points and its time.
With --delaunay JITTER (a shell's input: outer sheet, inner sheet, then its layers) builds the
shell as Levine et al. 2014 sec. 4 do: a plain Delaunay tetrahedralization of all the points
(`tetgen -zQ`), tets with every corner on the outer or every corner on the inner sheet left out;
the layers' points moved along their sheet by JITTER times the mean edge (0: as perifrac places
them); prints its time, the tets kept, their volume against the shell's and the share of slivers.
A measurement behind bench/NOTES.md, not part of the build. Needs numpy and scipy (Debian:
python3-numpy python3-scipy).
  scripts/tetgen-surface.py DIR [--flip OUT] [--tetgen=-pq1.414a2.99765808e-08iO0zF] [--delaunay J]
"""
import argparse
import pathlib
import re
import shutil
import subprocess
import time

import numpy as np
from scipy.spatial import cKDTree


def read_smesh(path):
    words = path.read_text().split("\n")
    n = int(words[0].split()[0])
    points = np.array([[float(v) for v in line.split()[1:4]] for line in words[1 : 1 + n]])
    facets = int(words[1 + n].split()[0])
    tris = [[int(v) for v in line.split()[1:4]] for line in words[2 + n : 2 + n + facets]]
    return points, tris


def write_smesh(path, points, tris):
    with path.open("w") as f:
        f.write(f"{len(points)} 3 0 0\n")
        for k, p in enumerate(points):
            f.write(f"{k} {p[0]!r} {p[1]!r} {p[2]!r}\n")
        f.write(f"{len(tris)} 0\n")
        for t in tris:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")
        f.write("0\n0\n")


def edges_of(tris):
    """Each edge (low, high) with the triangles on it and their third corners."""
    edges = {}
    for t, (a, b, c) in enumerate(tris):
        for u, v, w in ((a, b, c), (b, c, a), (c, a, b)):
            edges.setdefault((min(u, v), max(u, v)), []).append((t, w))
    return edges


def encroached(points, tree, u, v):
    mid, radius = 0.5 * (points[u] + points[v]), 0.5 * np.linalg.norm(points[u] - points[v])
    return any(k not in (u, v) for k in tree.query_ball_point(mid, radius * (1 - 1e-12)))


def report(name, points, tris, inserted):
    tree = cKDTree(points)
    edges = edges_of(tris)
    by_surface = sum(encroached(points, tree, u, v) for u, v in edges)
    line = f"{name}: {len(points)} vertices, {len(tris)} triangles, {len(edges)} edges; encroached by a vertex: {by_surface}"
    if inserted is not None:
        layer = cKDTree(inserted)
        by_layer = sum(
            bool(layer.query_ball_point(0.5 * (points[u] + points[v]), 0.5 * np.linalg.norm(points[u] - points[v])))
            for u, v in edges
        )
        line += f", by an inserted point: {by_layer}"
    t = np.array(tris)
    a, b, c = points[t[:, 0]], points[t[:, 1]], points[t[:, 2]]

    def angle(x, y, z):
        u, v = y - x, z - x
        cos = (u * v).sum(1) / np.linalg.norm(u, axis=1) / np.linalg.norm(v, axis=1)
        return np.degrees(np.arccos(np.clip(cos, -1, 1)))

    largest = np.maximum(np.maximum(angle(a, b, c), angle(b, c, a)), angle(c, a, b))
    print(f"{line}; obtuse triangles: {int((largest > 90.0001).sum())}")


def flip_encroached(points, tris):
    """One pass of flips of encroached edges; returns the count flipped."""
    tree = cKDTree(points)
    edges = edges_of(tris)
    used, flipped = set(), 0

    def normal(t):
        return np.cross(points[t[1]] - points[t[0]], points[t[2]] - points[t[0]])

    for (u, v), sides in edges.items():
        if len(sides) != 2 or not encroached(points, tree, u, v):
            continue
        (t1, w1), (t2, w2) = sides
        if t1 in used or t2 in used or (min(w1, w2), max(w1, w2)) in edges or encroached(points, tree, w1, w2):
            continue
        k = [tris[t1][(k + 2) % 3] for k in range(3)].index(w1)
        x, y = tris[t1][k], tris[t1][(k + 1) % 3]  # t1 = (x, y, w1), t2 holds (y, x, w2)
        new1, new2 = (x, w2, w1), (w2, y, w1)
        facing = normal((x, y, w1))
        if np.dot(normal(new1), facing) <= 0 or np.dot(normal(new2), facing) <= 0:
            continue
        tris[t1], tris[t2] = list(new1), list(new2)
        used |= {t1, t2}
        flipped += 1
    return flipped


def run_tetgen(switches, folder):
    work = pathlib.Path(folder) / "tetgen-run"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir()
    for name in ("in.smesh", "in.a.node"):
        if (pathlib.Path(folder) / name).exists():
            shutil.copy(pathlib.Path(folder) / name, work / name)
    start = time.monotonic()
    out = subprocess.run(["tetgen", switches.replace("Q", "") + "V", str(work / "in.smesh")],
                         capture_output=True, text=True, check=False)
    wall = time.monotonic() - start
    if out.returncode != 0:
        print(f"  tetgen failed ({out.returncode}): {out.stderr.strip()[-200:]}")
        return
    text = out.stdout

    def number(pattern):
        m = re.search(pattern, text)
        return m.group(1) if m else "?"

    refinement = number(r"Refinement seconds:\s+([0-9.]+)")
    tets = number(r"Mesh tetrahedra:\s+(\d+)")
    on_segments = number(r"Steiner points on segments:\s+(\d+)")
    on_facets = number(r"Steiner points on facets:\s+(\d+)")
    inside = number(r"Steiner points inside domain:\s+(\d+)")
    print(f"  tetgen {switches}: {wall:.2f} s wall (refinement {refinement} s), {tets} tets, Steiner points "
          f"on segments {on_segments}, on facets {on_facets}, inside {inside}")
    nodes = np.array(read_rows(work / "in.1.node", 3))
    elements = np.array(read_rows(work / "in.1.ele", 4), dtype=np.int64)
    print(f"  tets by volume over the median: {sliver_shares(tet_volumes(nodes, elements))}")
    shutil.rmtree(work, ignore_errors=True)


def tet_volumes(nodes, tets):
    corners = nodes[tets]
    return np.abs(np.einsum("ij,ij->i", np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0]),
                            corners[:, 3] - corners[:, 0])) / 6


def sliver_shares(volume):
    median = np.median(volume)
    return ", ".join(f"{(volume < f * median).mean() * 100:.3f}% under {f:g}" for f in (1e-3, 1e-2, 1e-1))


def read_rows(path, columns):
    rows = path.read_text().split("\n")
    return [[float(v) for v in r.split()[1 : 1 + columns]] for r in rows[1 : 1 + int(rows[0].split()[0])]]


def layers_delaunay(points, tris, inserted, jitter, folder):
    """Levine's shell: the Delaunay tetrahedralization of the sheets and layers, filtered."""
    half = len(points) // 2
    if inserted is None or len(points) % 2 or len(inserted) % half:
        print("  --delaunay needs a shell's input (two sheets of equal size and whole layers)")
        return
    outer, inner = points[:half], points[half:]
    layers = inserted.reshape(-1, half, 3).copy()
    if jitter > 0:
        t = np.array([tri for tri in tris if max(tri) < half])
        edge = np.linalg.norm(outer[t[:, 0]] - outer[t[:, 1]], axis=1).mean()
        depth = (inner - outer) / np.linalg.norm(inner - outer, axis=1)[:, None]
        rng = np.random.default_rng(1)
        for layer in layers:
            move = rng.normal(scale=jitter * edge, size=layer.shape)
            layer += move - (move * depth).sum(1)[:, None] * depth  # along the sheet only
    every = np.vstack([outer, inner, layers.reshape(-1, 3)])
    work = pathlib.Path(folder) / "delaunay-run"
    shutil.rmtree(work, ignore_errors=True)
    work.mkdir()
    with (work / "in.node").open("w") as f:
        f.write(f"{len(every)} 3 0 0\n")
        for k, p in enumerate(every):
            f.write(f"{k} {p[0]!r} {p[1]!r} {p[2]!r}\n")
    start = time.monotonic()
    subprocess.run(["tetgen", "-zQ", str(work / "in.node")], check=True, capture_output=True)
    wall = time.monotonic() - start
    tets = np.array(read_rows(work / "in.1.ele", 4), dtype=np.int64)
    sheet = np.where(tets < half, 0, np.where(tets < 2 * half, 1, 2))
    kept = tets[~((sheet == 0).all(1) | (sheet == 1).all(1))]
    volume = tet_volumes(every, kept)
    t = np.array(tris)
    solid = np.einsum("ij,ij->i", points[t[:, 0]], np.cross(points[t[:, 1]], points[t[:, 2]])).sum() / 6
    print(f"  Levine's Delaunay (jitter {jitter:g}): {wall:.2f} s wall, {len(every)} points, {len(tets)} tets, "
          f"{len(kept)} kept, their volume {volume.sum() / solid - 1:+.2%} against the shell's; "
          f"tets by volume over the median: {sliver_shares(volume)}")
    shutil.rmtree(work, ignore_errors=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input", help="folder with in.smesh (and in.a.node)")
    parser.add_argument("--flip", metavar="OUT", help="write a copy with encroached edges flipped")
    parser.add_argument("--tetgen", metavar="SWITCHES", help="run tetgen with these switches (V added)")
    parser.add_argument("--delaunay", metavar="JITTER", type=float,
                        help="Levine's shell: a plain Delaunay of the sheets and layers, layers moved by JITTER")
    args = parser.parse_args()
    folder = pathlib.Path(args.input)
    points, tris = read_smesh(folder / "in.smesh")
    layer_file = folder / "in.a.node"
    inserted = None
    if layer_file.exists():
        rows = layer_file.read_text().split("\n")
        inserted = np.array([[float(v) for v in r.split()[1:4]] for r in rows[1 : 1 + int(rows[0].split()[0])]])
    report("input", points, tris, inserted)
    if args.tetgen:
        run_tetgen(args.tetgen, folder)
    if args.delaunay is not None:
        layers_delaunay(points, tris, inserted, args.delaunay, folder)
    if args.flip:
        out = pathlib.Path(args.flip)
        out.mkdir(parents=True, exist_ok=True)
        rounds = 0
        while rounds < 5 and flip_encroached(points, tris):
            rounds += 1
        write_smesh(out / "in.smesh", points, tris)
        if layer_file.exists():
            shutil.copy(layer_file, out / "in.a.node")
        report(f"flipped ({rounds} rounds)", points, tris, inserted)
        if args.tetgen:
            run_tetgen(args.tetgen, out)


if __name__ == "__main__":
    main()
