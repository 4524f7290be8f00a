#!/usr/bin/env python3
"""Distance between two OBJ frames of the same mesh, vertex by vertex: the largest and the RMS, in mm, and each
frame's lowest y. docs/performance.md ("Blender") compares the peer sheet's frames at a large step with a
fine-step reference this way; docs/garments.md compares a sewn dress with Codim-IPC's drape, whose file holds the
dress's vertices first and the body's after them (--first 15656). Usage: bench/obj_distance.py A.obj B.obj [--first N]"""
import math
import sys


def vertices(path):
    with open(path) as f:
        return [tuple(float(t) for t in line.split()[1:4]) for line in f if line.startswith("v ")]




def fail(message):
    print(f"obj_distance.py: {message}", file=sys.stderr)
    sys.exit(2)


args = sys.argv[1:]
first = None
if len(args) == 4 and args[2] == "--first" and args[3].isdigit() and int(args[3]) > 0:
    first = int(args[3])
    args = args[:2]
if len(args) != 2:
    fail("usage: bench/obj_distance.py A.obj B.obj [--first N]")
try:
    a, b = vertices(args[0]), vertices(args[1])
except (OSError, ValueError) as e:
    fail(f"{e}; expected two readable OBJ files of the same mesh")
if first is not None:
    if len(a) < first or len(b) < first:
        fail(f"{args[0]} has {len(a)} vertices, {args[1]} has {len(b)}; --first {first} needs at least that many in each")
    a, b = a[:first], b[:first]
if len(a) != len(b) or not a:
    fail(f"{args[0]} has {len(a)} vertices, {args[1]} has {len(b)}; expected the same mesh, at least one vertex")
d = [math.dist(p, q) for p, q in zip(a, b)]
print(f"max {1000 * max(d):.1f} mm  rms {1000 * math.sqrt(sum(x * x for x in d) / len(d)):.1f} mm  "
      f"lowest y {min(p[1] for p in a):.4f} vs {min(p[1] for p in b):.4f}")
