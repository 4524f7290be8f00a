#!/usr/bin/env python3
"""bench/garment_stats.py against hand-counted figures: a square of two triangles and a one-triangle panel sewn to
its bottom edge's midpoint, two frames, and a cube for the body. Usage: garment_stats_test.py TOOL SCRATCH_DIR"""
import os
import subprocess
import sys

tool, scratch = sys.argv[1], sys.argv[2]
os.makedirs(os.path.join(scratch, "frames"), exist_ok=True)
rest = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (1, 1, 0), (0.5, -0.1, 0), (0, -1, 0), (1, -1, 0)]
faces = "f 1 2 3\nf 2 4 3\nf 5 6 7\n"


def write(path, verts, extra=""):
    with open(path, "w") as f:
        f.write("".join(f"v {x} {y} {z}\n" for x, y, z in verts) + faces + extra)


write(os.path.join(scratch, "rest.obj"), rest, "seam 1\nstitch 4 0 1 0.5\n")
# Frame 0: vertex 1 pulled 0.2 m along x (edge 0-1 at 20 %, 1-2 at 10.45 %, 1-3 at 1.98 %); the stitch's point is
# then (0.6, 0, 0), 0.1414 m from vertex 4. Frame 1: the rest, vertex 4 lifted to 0.5 mm from its point, which
# stretches its edge to vertex 5 from sqrt(1.06) to sqrt(0.25 + 1.0005^2) m: 8.64 %.
write(os.path.join(scratch, "frames", "cloth.0000.obj"), [(1.2, 0, 0) if i == 1 else p for i, p in enumerate(rest)])
write(os.path.join(scratch, "frames", "cloth.0001.obj"), [(0.5, 0.0005, 0) if i == 4 else p for i, p in enumerate(rest)])
# A cube of side 0.2 round (1, 0, 0): vertex 1 is inside it in frame 1 only.
cube = [(1 + 0.1 * sx, 0.1 * sy, 0.1 * sz) for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]
quads = [(1, 2, 4, 3), (5, 7, 8, 6), (1, 5, 6, 2), (3, 4, 8, 7), (1, 3, 7, 5), (2, 6, 8, 4)]
with open(os.path.join(scratch, "cube.obj"), "w") as f:
    f.write("".join(f"v {x} {y} {z}\n" for x, y, z in cube))
    f.write("".join(f"f {a} {b} {c}\nf {a} {c} {d}\n" for a, b, c, d in quads))

failures = []


def run(*args):
    return subprocess.run([sys.executable, tool, *args], capture_output=True, text=True)


def expect(label, got, want):
    if got != want:
        failures.append(f"{label}:\n  got  {got!r}\n  want {want!r}")


r = run(os.path.join(scratch, "frames"), os.path.join(scratch, "rest.obj"))
expect("exit code", r.returncode, 0)
expect("output", r.stdout.splitlines(), [
    "frame    0  largest strain 20.00 %  edges past 15 %    1  stitches over 1 mm    1  widest gap 141.42 mm",
    "frame    1  largest strain  8.64 %  edges past 15 %    0  stitches over 1 mm    0  widest gap  0.50 mm",
    "2 frames: largest strain 20.00 %, stitches over 1 mm median 0.5 (largest 1), widest gap 141.4 mm",
])
r = run(os.path.join(scratch, "frames"), os.path.join(scratch, "rest.obj"), "--limit", "0.1", "--first", "1")
expect("--limit, --first", r.stdout.splitlines()[-1],
       "1 frames: largest strain 8.64 %, stitches over 1 mm median 0 (largest 0), widest gap 0.5 mm")
r = run(os.path.join(scratch, "frames"), os.path.join(scratch, "rest.obj"), "--limit", "0.1")
expect("edges past 10 %", r.stdout.splitlines()[0].split("past 10 %")[1].split()[0], "2")
try:
    import numpy  # noqa: F401  (the body test needs it)
    r = run(os.path.join(scratch, "frames"), os.path.join(scratch, "rest.obj"), "--body", os.path.join(scratch, "cube.obj"))
    expect("inside the body", [line.split("inside the body")[1].strip() for line in r.stdout.splitlines()[:2]],
           ["0", "1"])
    expect("inside summary", r.stdout.splitlines()[-1].endswith("vertices inside the body 1 in 1 frames"), True)
    # The same cube after the garment's 7 vertices and 3 triangles in one file, as in Codim-IPC's drape file.
    with open(os.path.join(scratch, "both.obj"), "w") as f:
        f.write("".join(f"v {x} {y} {z}\n" for x, y, z in rest + cube) + faces)
        f.write("".join(f"f {a + 7} {b + 7} {c + 7}\nf {a + 7} {c + 7} {d + 7}\n" for a, b, c, d in quads))
    r = run(os.path.join(scratch, "frames"), os.path.join(scratch, "rest.obj"), "--body",
            os.path.join(scratch, "both.obj"), "--body-after", "7")
    expect("--body-after", [line.split("inside the body")[1].strip() for line in r.stdout.splitlines()[:2]],
           ["0", "1"])
except ImportError:
    print("numpy missing: the body test is skipped")

write(os.path.join(scratch, "bad.obj"), rest, "stitch 4 0 9 0.5\n")
r = run(os.path.join(scratch, "frames"), os.path.join(scratch, "bad.obj"))
expect("bad stitch exit code", r.returncode, 2)
expect("bad stitch message", "bad.obj: stitch (4, 0, 9, 0.5) refers to a vertex outside 0..6" in r.stderr, True)
write(os.path.join(scratch, "badline.obj"), rest, "stitch 4 0 x 0.5\n")
r = run(os.path.join(scratch, "frames"), os.path.join(scratch, "badline.obj"))
expect("bad line", (r.returncode, "badline.obj:11: expected 'stitch' followed by numbers" in r.stderr), (2, True))

for f in failures:
    print("FAILED", f)
print(f"{len(failures)} failures")
sys.exit(1 if failures else 0)
