#!/usr/bin/env python3
"""Per-frame figures of a sewn garment run (docs/garments.md): the largest edge strain against the rest mesh, the
edges past a strain limit (by more than clothsim's strain-limit tolerance, 1e-3), the stitches whose gap is over
1 mm and the widest gap, and optionally the garment vertices inside the body. The rest mesh is the OBJ that holds the stitch records (Codim-IPC's stage); the frames
are clothsim's written OBJs of the same mesh (their first vertices are the garment's, in the same order).

Usage: bench/garment_stats.py FRAMES_DIR REST.obj [--limit S] [--first N] [--body PATTERN] [--body-after N]
  --limit S      strain limit whose excess is counted (default 0.15: issue 16's largest allowed strain)
  --first N      garment frames from frame N on (default all)
  --body PATTERN the body's OBJ (.gz read too) for each frame, '#' standing for the frame number
                 (e.g. ../shared/data/colliders/animated/cipc_rumba/shell#.obj.gz); counts the garment vertices
                 inside it by the parity of rays' crossings (Body.inside_count). Needs numpy.
  --body-after N the body is the part of that OBJ from vertex N on (Codim-IPC's drape file: the dress's 15,656
                 vertices, then the mannequin's)
Prints one line per frame, then a summary. Exit code 2 on bad input."""
import gzip
import math
import os
import re
import statistics
import sys


def fail(message):
    print(f"garment_stats.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_obj(path, want_faces):
    """Vertices, faces (0-based, first three corners) and stitch records (i, j, k, w) of an OBJ."""
    opener = gzip.open if path.endswith(".gz") else open
    verts, faces, stitches = [], [], []
    with opener(path, "rt") as f:
        for number, line in enumerate(f, 1):
            t = line.split()
            if not t:
                continue
            try:
                if t[0] == "v":
                    verts.append((float(t[1]), float(t[2]), float(t[3])))
                elif t[0] == "f" and want_faces:
                    faces.append(tuple(int(c.split("/")[0]) - 1 for c in t[1:4]))
                elif t[0] == "stitch":
                    stitches.append((int(t[1]), int(t[2]), int(t[3]), float(t[4])))
            except (IndexError, ValueError):
                fail(f"{path}:{number}: expected '{t[0]}' followed by numbers")
    return verts, faces, stitches


class Body:
    """A closed triangle mesh and, per ray axis, its triangles binned by the two other coordinates."""

    cell = 0.01

    def __init__(self, verts, faces):
        import numpy as np

        self.np = np
        b = np.asarray(verts)
        tri = np.asarray(faces)
        self.a0, self.e1, self.e2 = b[tri[:, 0]], b[tri[:, 1]] - b[tri[:, 0]], b[tri[:, 2]] - b[tri[:, 0]]
        self.corners = b[tri]
        self.bins = {}

    def _bins(self, axis):
        if axis not in self.bins:
            np, other = self.np, [k for k in range(3) if k != axis]
            c = self.corners[:, :, other]
            lo = np.floor(c.min(1) / self.cell).astype(int)
            hi = np.floor(c.max(1) / self.cell).astype(int)
            bins = {}
            for t in range(len(c)):
                for u in range(lo[t, 0], hi[t, 0] + 1):
                    for v in range(lo[t, 1], hi[t, 1] + 1):
                        bins.setdefault((u, v), []).append(t)
            self.bins[axis] = (other, bins)
        return self.bins[axis]

    def crossings_odd(self, x, axis):
        """Whether a ray from x along +axis (tilted a little off it, so it does not run along an edge) crosses
        the surface an odd number of times."""
        np = self.np
        other, bins = self._bins(axis)
        ts = bins.get(tuple(int(math.floor(x[k] / self.cell)) for k in other))
        if not ts:
            return False
        ts = np.array(ts)
        d = np.full(3, 1e-7)
        d[axis] = 1.0
        d[other[1]] = 2e-7
        p = x - self.a0[ts]
        h = np.cross(d, self.e2[ts])
        det = np.einsum("ij,ij->i", self.e1[ts], h)
        ok = np.abs(det) > 1e-18
        inv = np.where(ok, 1 / np.where(ok, det, 1), 0)
        u = inv * np.einsum("ij,ij->i", p, h)
        q = np.cross(p, self.e1[ts])
        v = inv * (q @ d)
        s = inv * np.einsum("ij,ij->i", self.e2[ts], q)
        return int((ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (s > 0)).sum()) % 2 == 1

    def inside_count(self, points):
        """Points inside: the ray along x says so, and one of the rays along y and z agrees (a ray grazing an edge,
        or an open or self-crossing part of the mesh, can miscount one of them; most points stop at the first)."""
        return sum(self.crossings_odd(x, 0) and (self.crossings_odd(x, 1) or self.crossings_odd(x, 2))
                   for x in self.np.asarray(points))


def main(argv):
    options = {"--limit": "0.15", "--first": "0", "--body": None, "--body-after": "0"}
    positional = []
    i = 0
    while i < len(argv):
        if argv[i] in options:
            if i + 1 >= len(argv):
                fail(f"{argv[i]} needs a value")
            options[argv[i]] = argv[i + 1]
            i += 2
        else:
            positional.append(argv[i])
            i += 1
    if len(positional) != 2:
        fail("usage: bench/garment_stats.py FRAMES_DIR REST.obj [--limit S] [--first N] [--body PATTERN] "
             "[--body-after N]")
    frames_dir, rest_path = positional
    try:
        limit, first, after = float(options["--limit"]), int(options["--first"]), int(options["--body-after"])
    except ValueError:
        after = -1
    if after < 0:
        fail("--limit takes a strain (0.15), --first a frame number, --body-after a vertex count (0 or more)")
    if options["--body"]:
        try:
            import numpy  # noqa: F401  (Body needs it)
        except ImportError:
            fail("--body needs numpy (Debian: python3-numpy)")
    try:
        rest, faces, stitches = read_obj(rest_path, True)
    except OSError as e:
        fail(f"{e}; expected the rest OBJ with the stitch records")
    if not faces:
        fail(f"{rest_path}: no faces; expected the garment's triangles")
    n = len(rest)
    edges = sorted({(min(a, b), max(a, b)) for f in faces for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0]))})
    rest_len = [math.dist(rest[a], rest[b]) for a, b in edges]
    for s in stitches:
        if not all(0 <= k < n for k in s[:3]):
            fail(f"{rest_path}: stitch {s} refers to a vertex outside 0..{n - 1}")
    try:
        names = sorted(f for f in os.listdir(frames_dir) if f.endswith(".obj"))
    except OSError as e:
        fail(f"{e}; expected a folder of written frames")
    frames = [(int(m.group(1)), f) for f in names if (m := re.search(r"(\d+)\.obj$", f)) and int(m.group(1)) >= first]
    if not frames:
        fail(f"{frames_dir}: no frame OBJs numbered {first} or later")
    rows, bodies = [], {}
    for number, name in frames:
        try:
            x, _, _ = read_obj(os.path.join(frames_dir, name), False)
        except OSError as e:
            fail(f"{e}; expected a readable frame OBJ")
        if len(x) < n:
            fail(f"{name} has {len(x)} vertices; the rest mesh {n}")
        x = x[:n]
        strain = [math.dist(x[a], x[b]) / l - 1 for (a, b), l in zip(edges, rest_len) if l > 0]
        gaps = []
        for a, b, c, w in stitches:
            gaps.append(math.dist(x[a], tuple((1 - w) * x[b][k] + w * x[c][k] for k in range(3))))
        row = {"frame": number, "strain": max(strain), "past": sum(s > limit + 1e-3 for s in strain),
               "open": sum(g > 1e-3 for g in gaps), "gap": max(gaps, default=0.0)}
        line = (f"frame {number:4d}  largest strain {100 * row['strain']:5.2f} %  edges past {100 * limit:g} % "
                f"{row['past']:4d}  stitches over 1 mm {row['open']:4d}  widest gap {1000 * row['gap']:5.2f} mm")
        if options["--body"]:
            body_path = options["--body"].replace("#", str(number))
            if body_path not in bodies:  # a static body is read and binned once
                try:
                    bv, bf, _ = read_obj(body_path, True)
                except OSError as e:
                    fail(f"{e}; expected the body for frame {number}")
                bv, bf = bv[after:], [tuple(k - after for k in f) for f in bf if min(f) >= after]
                if not bf or max(max(f) for f in bf) >= len(bv):
                    fail(f"{body_path}: expected triangles among its vertices {after} and after")
                bodies.clear()
                bodies[body_path] = Body(bv, bf)
            row["inside"] = bodies[body_path].inside_count(x)
            line += f"  inside the body {row['inside']}"
        rows.append(row)
        print(line, flush=True)
    opened = [r["open"] for r in rows]
    summary = (f"{len(rows)} frames: largest strain {100 * max(r['strain'] for r in rows):.2f} %, stitches over 1 mm "
               f"median {statistics.median(opened):g} (largest {max(opened)}), widest gap "
               f"{1000 * max(r['gap'] for r in rows):.1f} mm")
    if options["--body"]:
        inside = [r["inside"] for r in rows]
        summary += f", vertices inside the body {sum(inside)} in {sum(k > 0 for k in inside)} frames"
    print(summary)


if __name__ == "__main__":
    main(sys.argv[1:])
