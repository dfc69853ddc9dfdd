#!/usr/bin/env python3
"""Crack orientation of grid bodies in a run: for each body, the mean damage jump between face
neighbours across x, y and z in the rest configuration. Cracks running along y separate
x-neighbours, so a larger x/y ratio means more cracks along y.
Usage: scripts/crack-orientation.py RUN_DIR FRAME [SPACING]   (needs python3-numpy)"""
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


def main():
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


if __name__ == "__main__":
    main()
