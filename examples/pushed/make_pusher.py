#!/usr/bin/env python3
"""Writes the animated collider of examples/pushed/pushed.xml: a sphere (r = 0.15 m) that rises from under the
ground through a cloth lying there, lifts it, then swings side to side, one OBJ per frame
(frames/pusher.0001.obj ... 0072.obj at 24 fps), the same topology in every frame.
Run once before the scene:  python3 examples/pushed/make_pusher.py"""
import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "frames")
RINGS, SEGMENTS, R, FPS, FRAMES = 12, 24, 0.15, 24, 72


def sphere(cx, cy, cz):
    v = [(cx, cy + R, cz)]
    for i in range(1, RINGS):
        th = math.pi * i / RINGS
        for j in range(SEGMENTS):
            ph = 2 * math.pi * j / SEGMENTS
            v.append((cx + R * math.sin(th) * math.cos(ph), cy + R * math.cos(th), cz + R * math.sin(th) * math.sin(ph)))
    v.append((cx, cy - R, cz))
    ring = lambda i, j: 2 + (i - 1) * SEGMENTS + (j % SEGMENTS)  # 1-based OBJ index
    bottom = 2 + (RINGS - 1) * SEGMENTS
    f = []
    for j in range(SEGMENTS):  # counter-clockwise seen from outside: normals point out
        f.append((1, ring(1, j + 1), ring(1, j)))
        for i in range(1, RINGS - 1):
            f.append((ring(i, j), ring(i, j + 1), ring(i + 1, j + 1)))
            f.append((ring(i, j), ring(i + 1, j + 1), ring(i + 1, j)))
        f.append((bottom, ring(RINGS - 1, j), ring(RINGS - 1, j + 1)))
    return v, f


os.makedirs(OUT, exist_ok=True)
for frame in range(1, FRAMES + 1):
    t = (frame - 1) / FPS
    y = -R + 0.45 * min(t, 1.0)                            # rises 0.45 m in the first second
    x = 0.15 * math.sin(2 * math.pi * (t - 1.0)) if t > 1.0 else 0.0  # then swings at 1 Hz
    v, f = sphere(x, y, 0.0)
    with open(os.path.join(OUT, "pusher.%04d.obj" % frame), "w") as out:
        out.writelines("v %.6f %.6f %.6f\n" % p for p in v)
        out.writelines("f %d %d %d\n" % t for t in f)
print("wrote %d frames into %s" % (FRAMES, OUT))
