#!/usr/bin/env python3
"""The bunny at 128³ voxelized by peer libraries, beside `cargo bench --bench score -- bunny`.

Same mesh (`../shared/data/models/stanford-bunny.obj`, scaled per axis into
[-1/2, 1/2]³ as `Mesh::normalized` does), same grid (128³ cells over
[-1/2, 1/2]³, centre sampling). Measured, each with the median of `--runs`:

- open3d (Embree) parity, one ray per cell: `RaycastingScene.compute_occupancy`
- open3d (Embree) parity, one ray per row: `list_intersections` along +x, then
  the cells between pairs of crossings
- libigl fast winding number (Barnes-Hut, beta = 2) at every cell centre

Not run in CI. To run it:

    python3 -m venv /tmp/peers && /tmp/peers/bin/pip install numpy open3d libigl
    # open3d needs libusb: apt-get install -y libusb-1.0-0
    /tmp/peers/bin/python benches/peers.py [--data ../shared/data] [--runs 5] [--threads N]

The peers use every core unless `--threads 1` (open3d/Embree and libigl read
OMP_NUM_THREADS / the machine's cores); shapegen's voxelizer runs on one.
"""

import argparse
import os
import statistics
import sys
import time


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    here = os.path.dirname(os.path.abspath(__file__))
    ap.add_argument("--data", default=os.path.join(here, "..", "..", "shared", "data"))
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--threads", type=int, default=0, help="0 = all cores")
    ap.add_argument("--n", type=int, default=128)
    args = ap.parse_args()
    if args.threads:
        for k in ("OMP_NUM_THREADS", "TBB_NUM_THREADS", "MKL_NUM_THREADS"):
            os.environ[k] = str(args.threads)
    import numpy as np

    path = os.path.join(args.data, "models", "stanford-bunny.obj")
    if not os.path.exists(path):
        sys.exit(f"{path} not found (pass --data)")
    V, F = read_obj(path)
    lo, hi = V.min(axis=0), V.max(axis=0)
    V = (V - (lo + hi) / 2) / (hi - lo)
    n = args.n
    c = -0.5 + (np.arange(n) + 0.5) / n
    Z, Y, X = np.meshgrid(c, c, c, indexing="ij")
    cells = np.stack([X.ravel(), Y.ravel(), Z.ravel()], axis=1)
    print(f"bunny: {len(V)} vertices, {len(F)} triangles; {n}³ = {len(cells)} cells")

    def timed(name, f):
        times, out = [], None
        for _ in range(args.runs):
            t = time.perf_counter()
            out = f()
            times.append(time.perf_counter() - t)
        print(f"{name:48s} median {statistics.median(times) * 1e3:9.1f} ms  ({out} cells inside)")

    try:
        import open3d as o3d

        def scene():
            s = o3d.t.geometry.RaycastingScene()
            s.add_triangles(o3d.core.Tensor(V.astype(np.float32)), o3d.core.Tensor(F.astype(np.uint32)))
            return s

        def per_cell():
            occ = scene().compute_occupancy(o3d.core.Tensor(cells.astype(np.float32)))
            return int(occ.numpy().sum())

        def per_row():
            s = scene()
            zz, yy = np.meshgrid(c, c, indexing="ij")
            rays = np.zeros((n * n, 6), np.float32)
            rays[:, 0] = -1.0
            rays[:, 1] = yy.ravel()
            rays[:, 2] = zz.ravel()
            rays[:, 3] = 1.0
            hits = s.list_intersections(o3d.core.Tensor(rays))
            split = hits["ray_splits"].numpy().astype(np.int64)
            t = hits["t_hit"].numpy().astype(np.float64) - 1.0  # x of each crossing
            # Each row's crossings sorted, taken in pairs: cells whose centre
            # lies in [a, b) are inside (vectorized: no Python loop per row).
            row = np.repeat(np.arange(n * n), np.diff(split))
            order = np.lexsort((t, row))
            t, row = t[order], row[order]
            rank = np.arange(len(t)) - split[row]
            last = split[row + 1] - 1
            enter = np.flatnonzero((rank % 2 == 0) & (np.arange(len(t)) < last))
            return int((np.searchsorted(c, t[enter + 1]) - np.searchsorted(c, t[enter])).sum())

        timed("open3d parity, one ray per cell", per_cell)
        timed("open3d parity, one ray per row", per_row)
    except ImportError as e:
        print(f"open3d: not available ({e})")

    try:
        import igl

        Fi = F.astype(np.int64)
        timed("libigl fast winding number", lambda: int((np.abs(igl.fast_winding_number(V, Fi, cells)) >= 0.5).sum()))
    except ImportError as e:
        print(f"libigl: not available ({e})")


def read_obj(path):
    import numpy as np

    V, F = [], []
    with open(path) as f:
        for line in f:
            p = line.split()
            if not p:
                continue
            if p[0] == "v":
                V.append([float(x) for x in p[1:4]])
            elif p[0] == "f":
                idx = [int(x.split("/")[0]) for x in p[1:]]
                idx = [i - 1 if i > 0 else len(V) + i for i in idx]
                for k in range(1, len(idx) - 1):
                    F.append([idx[0], idx[k], idx[k + 1]])
    return np.array(V, np.float64), np.array(F, np.int64)


if __name__ == "__main__":
    main()
