"""Peer side by side on a real garment: the knife-pleat dress of Codim-IPC (the first 15,656 vertices / 29,456
triangles of garments/cipc/dress_knife_drape_with_body.obj, 14 pieces, sliver triangles), each piece hanging from
the vertices within 1 cm of its top, no collisions, for the same simulated time in Blender's cloth modifier, baked
headless, and in clothsim, in one run, on one machine.

  blender -b --factory-startup --python-exit-code 1 --python bench/peer_dress.py -- CLOTHSIM_BIN SCRATCH_DIR \
      [--dress PATH] [--seconds 0.5] [--fps 24] [--quality 5] [--tension 15] [--timestep 0.0083333] \
      [--preconditioners cholesky,multigrid] [--cg-tolerance 1e-3] [--threads 2] [--stiffness N_PER_M] \
      [--bendings springs,dihedral] [--bend-modulus 1e-5]

bench/peer_dress.sh wraps it and exits 77 (skipped) where blender or the data are missing. Prints one row per run:
the step, the wall and CPU seconds, the largest edge strain over the frames (measured the same way on both: the
mesh's edges against their rest lengths in the OBJ), clothsim's CG iterations and factorisations a step, and the
ratio of Blender's wall and CPU time to each clothsim run's.

Matched model as in bench/peer_blender.py: Blender's spring constant taken as tension / rest length, so clothsim gets
stiffness = tension / (mean edge length) N/m per spring unless --stiffness is given (Blender's tension model keeps
the dress less stretched than that: --stiffness at matched strain is the like-for-like run); the same mass (0.2 kg/m^2 lumped by area in clothsim, the
total spread evenly over the vertices in Blender); gravity 9.81 m/s^2 along -y.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from peer_run import run_clothsim_timed  # noqa: E402
from peer_sheet import bake_cloth, reset_scene  # noqa: E402

import bpy
import numpy as np

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
ap = argparse.ArgumentParser(prog="peer_dress.py")
ap.add_argument("clothsim", help="path to the clothsim binary")
ap.add_argument("scratch", help="folder for the extracted dress, the bake, the scenes and their frames")
ap.add_argument("--dress", default=os.path.join(os.path.dirname(__file__), "..", "..", "shared", "data", "garments",
                                                 "cipc", "dress_knife_drape_with_body.obj"))
ap.add_argument("--seconds", type=float, default=0.5, help="simulated time")
ap.add_argument("--fps", type=int, default=24)
ap.add_argument("--quality", type=int, default=5, help="Blender's quality steps (substeps per frame)")
ap.add_argument("--tension", type=float, default=15.0, help="Blender tension/shear stiffness (its default 15)")
ap.add_argument("--stiffness", type=float, default=0.0,
                help="clothsim N/m a spring (default tension / mean edge length); raise it to match Blender's strain")
ap.add_argument("--timestep", type=float, default=1.0 / 120, help="clothsim step, s")
ap.add_argument("--preconditioners", default="cholesky,multigrid", help="clothsim runs, comma-separated")
ap.add_argument("--cg-tolerance", type=float, default=1e-3, help="clothsim implicit: relative CG residual")
ap.add_argument("--threads", type=int, default=2, help="threads for both")
ap.add_argument("--bendings", default="springs",
                help="clothsim bending models, comma-separated: springs (bend=\"0.1\"), dihedral (--bend-modulus)")
ap.add_argument("--bend-modulus", type=float, default=1e-5, help="bending modulus D of the dihedral runs, N m")
args = ap.parse_args(argv)

VERTICES, TRIANGLES = 15656, 29456
fps = args.fps
frames = round(args.seconds * fps)
seconds = frames / fps
os.makedirs(args.scratch, exist_ok=True)


def extract_dress():
    """The dress's vertices and triangles (the file's first ones; the mannequin follows), written as an OBJ."""
    verts, tris = [], []
    with open(args.dress) as f:
        for line in f:
            if line.startswith("v ") and len(verts) < VERTICES:
                verts.append([float(t) for t in line.split()[1:4]])
            elif line.startswith("f ") and len(tris) < TRIANGLES:
                tris.append([int(t.split("/")[0]) - 1 for t in line.split()[1:4]])
    verts, tris = np.array(verts), np.array(tris)
    path = os.path.join(args.scratch, "dress.obj")
    with open(path, "w") as f:
        f.writelines(f"v {x!r} {y!r} {z!r}\n" for x, y, z in verts)
        f.writelines(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tris)
    return path, verts, tris


def hanging_pins(verts, tris):
    """Each connected piece's vertices within 1 cm of its highest one (y up)."""
    parent = list(range(len(verts)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for t in tris:
        for a, b in ((t[0], t[1]), (t[1], t[2])):
            ra, rb = root(a), root(b)
            if ra != rb:
                parent[ra] = rb
    piece = np.array([root(i) for i in range(len(verts))])
    top = {p: verts[piece == p, 1].max() for p in np.unique(piece)}
    return [i for i in range(len(verts)) if verts[i, 1] >= top[piece[i]] - 0.01], len(top)


def edge_strain(co, edges, rest):
    d = co[edges[:, 1]] - co[edges[:, 0]]
    return float(np.max((np.linalg.norm(d, axis=1) - rest) / rest))


def run_blender(verts, tris, pins, mass):
    reset_scene(args.threads, fps, frames, (0, -9.81, 0))  # the OBJ is y-up; no axis conversion on either side
    mesh = bpy.data.meshes.new("dress")
    mesh.from_pydata(verts.tolist(), [], tris.tolist())
    mesh.update()
    obj = bpy.data.objects.new("dress", mesh)
    bpy.context.scene.collection.objects.link(obj)
    assert len(mesh.vertices) == len(verts)
    wall, cpu, positions = bake_cloth(obj, pins, args.quality, args.tension, mass / len(verts), frames)
    worst = max(edge_strain(pos, EDGES, REST) for pos in positions)
    return dict(peer=f"blender q{args.quality}", step=1.0 / (fps * args.quality), steps=frames * args.quality,
                wall=wall, cpu=cpu, max_strain=worst)


def read_obj_positions(path):
    with open(path) as f:
        return np.array([[float(t) for t in line.split()[1:4]] for line in f if line.startswith("v ")])


def run_clothsim(obj_path, pins, stiffness, preconditioner, bending):
    name = preconditioner if bending == "springs" else f"{preconditioner}_{bending}"
    out = os.path.join(args.scratch, f"clothsim_{name}")
    xml = os.path.join(args.scratch, f"dress_{name}.xml")
    stats = os.path.join(args.scratch, f"dress_{name}_stats.json")
    bend = 'bend="0.1"' if bending == "springs" else f'bendModulus="{args.bend_modulus!r}"'
    steps_per_frame = max(1, round(1.0 / (fps * args.timestep)))
    with open(xml, "w") as f:
        f.write(f"""<?xml version="1.0"?>
<!-- bench/peer_dress.py: the knife-pleat dress, each piece hanging from its top centimetre, no collisions -->
<scene>
  <simulation timestep="{1.0 / (fps * steps_per_frame)!r}" fps="{fps}" startFrame="1" endFrame="{1 + frames}"
              integrator="implicit" cgTolerance="{args.cg_tolerance!r}" preconditioner="{preconditioner}"
              gravity="0 -9.81 0"/>
  <forces><airDamping value="0.1"/></forces>
  <cloth name="dress" obj="{obj_path}" saveDir="{out}" saveName="dress" bending="{bending}">
    <density value="0.2"/>
    <stiffness value="{stiffness!r}" {bend}/>
    <damping value="0.1"/>
    <pins vertices="{' '.join(map(str, pins))}"/>
  </cloth>
</scene>
""")
    wall, cpu, st = run_clothsim_timed(args.clothsim, xml, args.threads, stats)
    worst = 0.0
    for frame in range(2, 2 + frames):
        worst = max(worst, edge_strain(read_obj_positions(os.path.join(out, f"dress.{frame:04d}.obj")), EDGES, REST))
    fr = st["frames"]
    return dict(peer=f"clothsim {name}", step=st["dt"], steps=st["steps"], wall=wall, cpu=cpu,
                max_strain=worst, cg=st.get("cg_iterations", 0) / max(1, st["steps"]),
                factorizations=sum(f.get("factorizations", 0) for f in fr), failed=st.get("implicit_failed_steps", 0))


obj_path, verts, tris = extract_dress()
pins, pieces = hanging_pins(verts, tris)
EDGES = np.unique(np.sort(np.concatenate([tris[:, [0, 1]], tris[:, [1, 2]], tris[:, [2, 0]]]), axis=1), axis=0)
REST = np.linalg.norm(verts[EDGES[:, 1]] - verts[EDGES[:, 0]], axis=1)
area = 0.5 * np.linalg.norm(np.cross(verts[tris[:, 1]] - verts[tris[:, 0]], verts[tris[:, 2]] - verts[tris[:, 0]]),
                            axis=1).sum()
stiffness = args.stiffness or args.tension / REST.mean()
runs = [run_clothsim(obj_path, pins, stiffness, p, b) for b in args.bendings.split(",") if b
        for p in args.preconditioners.split(",") if p]
bl = run_blender(verts, tris, pins, 0.2 * area)
print(f"knife-pleat dress: {len(verts)} vertices, {len(tris)} triangles, {pieces} pieces, {len(pins)} pinned; "
      f"{seconds:g} s simulated, {args.threads} threads; Blender quality {args.quality}, tension {args.tension:g} "
      f"(clothsim {stiffness:.4g} N/m a spring, cgTolerance {args.cg_tolerance:g})")
print(f"{'run':<26} {'step_s':>9} {'steps':>6} {'wall_s':>8} {'cpu_s':>8} {'max_strain':>10} {'cg/step':>8} "
      f"{'factor':>6} {'failed':>6} {'blender_wall/run':>16} {'blender_cpu/run':>15}")
for r in runs + [bl]:
    print(f"{r['peer']:<26} {r['step']:>9.4g} {r['steps']:>6d} {r['wall']:>8.3f} {r['cpu']:>8.3f} "
          f"{r['max_strain']:>10.4f} {r.get('cg', 0):>8.1f} {r.get('factorizations', 0):>6d} {r.get('failed', 0):>6d} "
          f"{bl['wall'] / r['wall']:>16.2f} {bl['cpu'] / r['cpu']:>15.2f}")
