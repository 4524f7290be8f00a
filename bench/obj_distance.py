#!/usr/bin/env python3
"""Distance between two OBJ frames of the same mesh, vertex by vertex: the largest and the RMS, in mm, and each
frame's lowest y. docs/performance.md ("Blender") compares the peer sheet's frames at a large step with a
fine-step reference this way. Usage: bench/obj_distance.py A.obj B.obj"""
import math
import sys


def vertices(path):
    with open(path) as f:
        return [tuple(float(t) for t in line.split()[1:4]) for line in f if line.startswith("v ")]




def fail(message):
    print(f"obj_distance.py: {message}", file=sys.stderr)
    sys.exit(2)


if len(sys.argv) != 3:
    fail("usage: bench/obj_distance.py A.obj B.obj")
try:
    a, b = vertices(sys.argv[1]), vertices(sys.argv[2])
except (OSError, ValueError) as e:
    fail(f"{e}; expected two readable OBJ files of the same mesh")
if len(a) != len(b) or not a:
    fail(f"{sys.argv[1]} has {len(a)} vertices, {sys.argv[2]} has {len(b)}; expected the same mesh, at least one vertex")
d = [math.dist(p, q) for p, q in zip(a, b)]
print(f"max {1000 * max(d):.1f} mm  rms {1000 * math.sqrt(sum(x * x for x in d) / len(d)):.1f} mm  "
      f"lowest y {min(p[1] for p in a):.4f} vs {min(p[1] for p in b):.4f}")
