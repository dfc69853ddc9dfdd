#!/usr/bin/env python3
"""Crack orientation of grid bodies in a run: for each body, the mean damage jump between face
neighbours across x, y and z in the rest configuration. Cracks running along y separate
x-neighbours, so a larger x/y ratio means more cracks along y. With --about X,Y (an impact point
in the x-y plane), also per ring around it: how much of the jump in the plane runs radially
(radial cracks separate neighbours across the circumference) and its share against the jump
across the radius (circumferential cracks), so two runs' crack patterns can be compared.
Usage: scripts/crack-orientation.py RUN_DIR FRAME [SPACING] [--about X,Y]   (needs python3-numpy)"""
import sys
import numpy as np


def read_pfr(path):
    b = open(path, "rb").read()
    assert b[:8] == b"PFRAME\0\0", f"{path}: not a .pfr file"
    version, kind, n, frame, step, time, n_arrays = np.frombuffer(b, "<u4,<u4,<u8,<i8,<i8,<f8,<u4", 1, 8)[0].tolist()
    arrays, at = {}, 52
    for _ in range(n_arrays):
        name = b[at:at + 16].rstrip(b"\0").decode()
        type_code, c = np.frombuffer(b, "<u4", 2, at + 16).tolist()
        values = np.frombuffer(b, {1: "<f4", 2: "<i4"}[type_code], n * c, at + 24)
        arrays[name] = values.reshape(n, c) if c > 1 else values
        at += 24 + 4 * n * c
    return arrays


def rings(grid, origin, lam, about, count=6):
    """Per ring around `about`: the in-plane damage jump across the circumference and across the
    radius (each face pair's jump split by the squared cosines of its direction to the radius)."""
    radial, circumferential, outer = np.zeros(count), np.zeros(count), 0.0
    pairs = []
    for a in range(2):
        jump = np.abs(np.diff(grid, axis=a))
        idx = np.argwhere(~np.isnan(jump))
        mid = origin[:2] + lam * (idx[:, :2] + 0.5 * (np.arange(2) == a))
        rel = mid - np.asarray(about)
        r2 = np.maximum((rel ** 2).sum(axis=1), 1e-30)
        along = rel[:, a] ** 2 / r2  # the pair's direction against the radius, squared cosine
        pairs.append((np.sqrt(r2), jump[tuple(idx.T)], along))
        outer = max(outer, np.sqrt(r2).max())
    edges = np.linspace(0, outer, count + 1)
    for r, j, along in pairs:
        band = np.minimum(np.searchsorted(edges, r, side="right") - 1, count - 1)
        np.add.at(radial, band, j * (1 - along))
        np.add.at(circumferential, band, j * along)
    return edges, radial, circumferential


def main():
    about = None
    if "--about" in sys.argv:
        k = sys.argv.index("--about")
        about = [float(v) for v in sys.argv[k + 1].split(",")]
        del sys.argv[k:k + 2]
    run, frame = sys.argv[1], int(sys.argv[2])
    rest = read_pfr(f"{run}/rest.pfr")
    cur = read_pfr(f"{run}/frame_{frame:05d}.pfr")
    x, body, dmg = rest["position"], cur["body"], cur["damage"]
    for b in np.unique(body):
        m = body == b
        lam = float(sys.argv[3]) if len(sys.argv) > 3 else np.cbrt(np.median(rest["volume"][m]))
        idx = np.round((x[m] - x[m].min(axis=0)) / lam).astype(int)
        grid = np.full(idx.max(axis=0) + 1, np.nan)
        grid[idx[:, 0], idx[:, 1], idx[:, 2]] = dmg[m]
        jumps = [np.nanmean(np.abs(np.diff(grid, axis=a))) if grid.shape[a] > 1 else np.nan for a in range(3)]
        print(f"body {b}: mean damage {dmg[m].mean():.3f}; damage jump across x {jumps[0]:.4f}, y {jumps[1]:.4f}, "
              f"z {jumps[2]:.4f}; x/y {jumps[0] / jumps[1]:.3f}")
        if about is not None:
            edges, radial, circ = rings(grid, x[m].min(axis=0), lam, about)
            for k in range(len(radial)):
                total = radial[k] + circ[k]
                share = radial[k] / total if total > 0 else float("nan")
                print(f"  ring {edges[k]:.4f}-{edges[k + 1]:.4f} m: jump across the circumference (radial cracks) "
                      f"{radial[k]:.1f}, across the radius (circumferential cracks) {circ[k]:.1f}, radial share {share:.3f}")


if __name__ == "__main__":
    main()
