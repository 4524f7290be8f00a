#!/usr/bin/env python3
"""The highest frequency of each triangle of an OBJ alone, with the mesh's area-lumped masses, under two stretch
models: the triangle's three edge springs of stiffness k (clothsim's springs), and a linear (constant-strain)
isotropic membrane with E t = 2 k / sqrt(3) and Poisson's ratio 1/3, the membrane a regular lattice of such springs
approximates. An element's frequency bounds the whole mesh's from below (docs/stability.md), and h^2 omega^2 sets
how ill-conditioned the backward-Euler matrix is; docs/performance.md uses this to ask whether an area-weighted
membrane would tame the knife-pleat dress's sliver triangles.

  bench/element_frequencies.py MESH.obj [--vertices N] [--triangles N] [--stiffness 1000] [--density 0.2]

--vertices / --triangles keep the file's first N of each (the dress in dress_knife_drape_with_body.obj: 15656 and
29456). Needs numpy."""
import argparse
import sys

import numpy as np

ap = argparse.ArgumentParser(prog="element_frequencies.py")
ap.add_argument("obj")
ap.add_argument("--vertices", type=int, default=0, help="keep the first N vertices (0: all)")
ap.add_argument("--triangles", type=int, default=0, help="keep the first N triangles (0: all)")
ap.add_argument("--stiffness", type=float, default=1000.0, help="spring stiffness k, N/m")
ap.add_argument("--density", type=float, default=0.2, help="kg/m^2")
args = ap.parse_args()

verts, tris = [], []
try:
    with open(args.obj) as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v" and (args.vertices == 0 or len(verts) < args.vertices):
                verts.append([float(x) for x in t[1:4]])
            elif t[0] == "f" and (args.triangles == 0 or len(tris) < args.triangles):
                if len(t) != 4:
                    sys.exit(f"element_frequencies.py: {args.obj}: expected triangles, found a face of {len(t) - 1}")
                tris.append([int(x.split("/")[0]) - 1 for x in t[1:4]])
except OSError as e:
    sys.exit(f"element_frequencies.py: {e}")
V, F = np.array(verts), np.array(tris)
if len(F) == 0 or F.max() >= len(V):
    sys.exit(f"element_frequencies.py: {args.obj}: no triangles, or a face past the vertices kept")

P = V[F]
e1, e2 = P[:, 1] - P[:, 0], P[:, 2] - P[:, 0]
cross = np.cross(e1, e2)
area = 0.5 * np.linalg.norm(cross, axis=1)
live = area > 0
F, e1, e2, cross, area = F[live], e1[live], e2[live], cross[live], area[live]
mass = np.zeros(len(V))
for k in range(3):
    np.add.at(mass, F[:, k], args.density * area / 3)
# Each triangle in its own plane: corner 0 at the origin, edge 0-1 along the first axis.
u = e1 / np.linalg.norm(e1, axis=1)[:, None]
w = np.cross(cross / (2 * area)[:, None], u)
X = np.stack([np.zeros((len(F), 2)), np.c_[(e1 * u).sum(1), (e1 * w).sum(1)],
              np.c_[(e2 * u).sum(1), (e2 * w).sum(1)]], 1)
T = len(F)


def highest(K):
    """sqrt of the largest eigenvalue of M^-1/2 K M^-1/2 per element (6 x 6: x, y of three corners)."""
    s = np.repeat(1 / np.sqrt(mass[F]), 2, axis=1)
    return np.sqrt(np.maximum(np.linalg.eigvalsh(K * s[:, :, None] * s[:, None, :])[:, -1], 0))


k = args.stiffness
springs = np.zeros((T, 6, 6))
for a, b in ((0, 1), (1, 2), (2, 0)):
    d = X[:, b] - X[:, a]
    n = d / np.linalg.norm(d, axis=1)[:, None]
    block = k * n[:, :, None] * n[:, None, :]
    for i, j, sign in ((a, a, 1), (b, b, 1), (a, b, -1), (b, a, -1)):
        springs[:, 2 * i:2 * i + 2, 2 * j:2 * j + 2] += sign * block
x, y = X[:, :, 0], X[:, :, 1]
bx = np.stack([y[:, 1] - y[:, 2], y[:, 2] - y[:, 0], y[:, 0] - y[:, 1]], 1) / (2 * area)[:, None]
cy = np.stack([x[:, 2] - x[:, 1], x[:, 0] - x[:, 2], x[:, 1] - x[:, 0]], 1) / (2 * area)[:, None]
B = np.zeros((T, 3, 6))
for i in range(3):
    B[:, 0, 2 * i], B[:, 1, 2 * i + 1] = bx[:, i], cy[:, i]
    B[:, 2, 2 * i], B[:, 2, 2 * i + 1] = cy[:, i], bx[:, i]
nu, et = 1 / 3, 2 * k / np.sqrt(3)
D = et / (1 - nu ** 2) * np.array([[1, nu, 0], [nu, 1, 0], [0, 0, (1 - nu) / 2]])
membrane = area[:, None, None] * np.einsum("tki,kl,tlj->tij", B, D, B)

ws, wm = highest(springs), highest(membrane)
print(f"{args.obj}: {len(V)} vertices, {T} triangles, k {k:g} N/m, {args.density:g} kg/m^2")
print(f"{'model':<9} {'max':>9} {'99.9%':>9} {'99%':>9} {'median':>9}  rad/s")
for name, om in (("springs", ws), ("membrane", wm)):
    print(f"{name:<9} {om.max():>9.3g} {np.percentile(om, 99.9):>9.3g} {np.percentile(om, 99):>9.3g} "
          f"{np.median(om):>9.3g}")
ratio = wm / ws
print(f"membrane / springs, per element: median {np.median(ratio):.2f}, 99% {np.percentile(ratio, 99):.2f}, "
      f"max {ratio.max():.3g}")
for name, om in (("springs", ws), ("membrane", wm)):
    i = om.argmax()
    edges = np.linalg.norm(X[i][[1, 2, 0]] - X[i], axis=1) * 1e3
    print(f"highest {name} element: edges {' '.join(f'{e:.3g}' for e in edges)} mm, area {area[i] * 1e6:.3g} mm^2")
