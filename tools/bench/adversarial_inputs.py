#!/usr/bin/env python3
"""Nasty point sets for tools/bench/adversarial_equivalence.sh (standard library only).

    adversarial_inputs.py OUTDIR [SCALE]

Writes one file per case into OUTDIR (.xyz text with repr() doubles, which read back
exactly, ascii PLY, or binary float32 PCD) and prints their names. SCALE (default 1.0)
multiplies the point counts (1e3..3e5 at 1.0). Deterministic (fixed seeds)."""
import math
import os
import random
import struct
import sys


def write_xyz(path, pts):
    with open(path, "w") as f:
        f.write("# adversarial_inputs.py\n")
        for x, y, z in pts:
            f.write("%r %r %r\n" % (x, y, z))


def write_ply(path, pts):
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\n" % len(pts))
        f.write("property double x\nproperty double y\nproperty double z\nend_header\n")
        for x, y, z in pts:
            f.write("%r %r %r\n" % (x, y, z))


def write_pcd_f32(path, pts):
    with open(path, "wb") as f:
        f.write(("VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
                 "WIDTH %d\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\nDATA binary\n"
                 % (len(pts), len(pts))).encode())
        for x, y, z in pts:
            f.write(struct.pack("<fff", x, y, z))


def n_(k, scale):
    return max(1, int(k * scale))


def cases(scale):
    r = random.Random(20261127)
    out = {}

    # exact integer grid with round holes
    m = n_(200, math.sqrt(scale))
    pts = []
    holes = [(m * 0.3, m * 0.3, m * 0.12), (m * 0.7, m * 0.6, m * 0.2), (m * 0.2, m * 0.8, 3.0)]
    for i in range(m):
        for j in range(m):
            if any((i - cx) ** 2 + (j - cy) ** 2 < rr * rr for cx, cy, rr in holes):
                continue
            pts.append((float(i), float(j), float((i * 7 + j * 3) % 11)))
    out["grid_holes.xyz"] = pts

    # lattice rotated by 30 degrees (inexact rotation) and by 3-4-5 (exact rationals)
    m = n_(150, math.sqrt(scale))
    c, s = math.cos(math.pi / 6), math.sin(math.pi / 6)
    pts = [(i * c - j * s, i * s + j * c, 0.01 * i) for i in range(m) for j in range(m)]
    out["rot_lattice30.xyz"] = pts
    pts = [((4 * i - 3 * j) / 5.0, (3 * i + 4 * j) / 5.0, 0.0) for i in range(m) for j in range(m)]
    out["rot_lattice345.ply"] = pts

    # exactly cocircular integer points: x^2 + y^2 = R2 for R2 with many representations
    pts = []
    for R2 in (5 ** 2 * 13 ** 2 * 17 ** 2, 5 ** 4 * 13 ** 2, 65 ** 2, 25, 5 ** 2 * 13 ** 2 * 17 ** 2 * 29 ** 2):
        R = math.isqrt(R2)
        for x in range(-R, R + 1):
            y2 = R2 - x * x
            y = math.isqrt(y2)
            if y * y == y2:
                for yy in {y, -y}:
                    pts.append((float(x), float(yy), float(R)))
    pts.append((0.0, 0.0, 0.0))
    out["cocircular_exact.xyz"] = pts
    # few floating circles (each circle's points are not exactly cocircular)
    pts = [(0.0, 0.0, 1.0)]
    k = n_(400, scale)
    for ring in range(1, 9):
        for a in range(k):
            t = 2 * math.pi * a / k
            pts.append((ring * math.cos(t), ring * math.sin(t), float(ring)))
    out["circles.xyz"] = pts

    # many duplicates with different z, shuffled (every --duplicates rule is run on it)
    pts = []
    n = n_(20000, scale)
    for q in range(n):
        x, y = float(r.randrange(0, 400)) * 0.25, float(r.randrange(0, 400)) * 0.25
        for _ in range(r.randrange(1, 5)):
            pts.append((x, y, round(r.uniform(-5, 5), 3)))
    r.shuffle(pts)
    out["duplicates.xyz"] = pts

    # -0.0 and +0.0 coordinates, duplicated across signs with different z
    pts = []
    for i in range(-30, 31):
        for j in range(-30, 31):
            x = float(i) if i else r.choice((0.0, -0.0))
            y = float(j) if j else r.choice((0.0, -0.0))
            pts.append((x, y, float(i + j)))
    for z in (3.0, -1.0, 7.0, -0.0):
        pts.append((r.choice((0.0, -0.0)), r.choice((0.0, -0.0)), z))
        pts.append((-0.0, 5.0, z))
        pts.append((5.0, -0.0, z + 1))
    out["signed_zero.xyz"] = pts

    # huge UTM offsets, 1e-3 steps
    pts = []
    n = n_(30000, scale)
    for _ in range(n):
        x = 500000.0 + r.randrange(0, 200000) * 1e-3
        y = 5000000.0 + r.randrange(0, 200000) * 1e-3
        pts.append((round(x, 3), round(y, 3), round(r.uniform(100, 110), 3)))
    out["utm_mm.xyz"] = pts
    # an exact UTM millimetre grid
    m = n_(120, math.sqrt(scale))
    out["utm_grid.xyz"] = [(round(612345.0 + i * 1e-3, 3), round(5123456.0 + j * 1e-3, 3), 0.5)
                           for i in range(m) for j in range(m)]

    # thin strip 1e4 : 1 (and its transpose)
    n = n_(20000, scale)
    pts = [(r.uniform(0, 10000), r.uniform(0, 1), r.uniform(0, 1)) for _ in range(n)]
    out["strip_x.xyz"] = pts
    out["strip_y.xyz"] = [(y, x, z) for x, y, z in pts]

    # two clusters 1e6 apart
    n = n_(5000, scale)
    pts = [(r.random(), r.random(), 0.0) for _ in range(n)]
    pts += [(1e6 + r.random(), 1e6 + r.random(), 1.0) for _ in range(n)]
    out["two_clusters.xyz"] = pts

    # collinear rows (with long exact rows and a few points between)
    pts = []
    n = n_(2000, scale)
    for row in range(6):
        for i in range(n):
            pts.append((i * 0.5, row * 10.0, float(row)))
    pts += [(r.uniform(0, n * 0.5), r.uniform(0, 50), 0.0) for _ in range(20)]
    out["collinear_rows.xyz"] = pts
    # every point on one line: must fail cleanly, identically on every path
    out["all_collinear.xyz"] = [(i * 1.0, 2 * i * 1.0, 0.0) for i in range(100)]

    # a few points
    out["few3.xyz"] = [(0.0, 0.0, 0.0), (1.0, 0.0, 1.0), (0.0, 1.0, 2.0)]
    out["few4_square.xyz"] = [(0.0, 0.0, 0.0), (1.0, 0.0, 1.0), (1.0, 1.0, 2.0), (0.0, 1.0, 3.0)]
    out["few5_cross.xyz"] = [(0.0, 0.0, 0.0), (1.0, 0.0, 1.0), (-1.0, 0.0, 2.0), (0.0, 1.0, 3.0), (0.0, -1.0, 4.0)]
    out["few7.xyz"] = [(r.uniform(0, 1), r.uniform(0, 1), 0.0) for _ in range(7)]
    out["few10_dups.xyz"] = [(float(i % 4), float(i // 4 % 3), float(i)) for i in range(10)] + [(0.0, 0.0, -1.0)]

    # points exactly on power-of-two block/tile boundaries
    pts = []
    n = n_(40000, scale)
    for _ in range(n):
        pts.append((r.randrange(0, 1024 * 8) / 8.0, r.randrange(0, 1024 * 8) / 8.0, 0.0))
    for k in range(0, 1025, 64):
        for t in range(0, 1025, 4):
            pts.append((float(k), float(t), 1.0))
            pts.append((float(t), float(k), 1.0))
    out["pow2_boundaries.xyz"] = pts

    # a dense cluster (1e5 points in 1 m^2) beside a sparse area
    n = n_(100000, scale)
    pts = [(500 + r.random(), 500 + r.random(), r.random()) for _ in range(n)]
    pts += [(r.uniform(0, 1000), r.uniform(0, 1000), r.uniform(0, 10)) for _ in range(n_(5000, scale))]
    out["dense_sparse.xyz"] = pts

    # float32-rounded coordinates (binary PCD): many exact float duplicates and near-collinear
    n = n_(50000, scale)
    pts = []
    for _ in range(n):
        x = struct.unpack("<f", struct.pack("<f", 100000.0 + r.uniform(0, 50)))[0]
        y = struct.unpack("<f", struct.pack("<f", 200000.0 + r.uniform(0, 50)))[0]
        pts.append((x, y, r.uniform(0, 3)))
    out["float_rounded.pcd"] = pts
    return out


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    outdir = sys.argv[1]
    scale = float(sys.argv[2]) if len(sys.argv) > 2 else 1.0
    os.makedirs(outdir, exist_ok=True)
    for name, pts in cases(scale).items():
        path = os.path.join(outdir, name)
        if name.endswith(".ply"):
            write_ply(path, pts)
        elif name.endswith(".pcd"):
            write_pcd_f32(path, pts)
        else:
            write_xyz(path, pts)
        print(name, len(pts))


if __name__ == "__main__":
    main()
