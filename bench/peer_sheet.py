"""The peer sheet, shared by bench/peer_blender.py and bench/peer_chart.py: a side x side grid, 1 m square, 1 kg,
hanging from the two corners of one edge, starting flat, no collisions; baked in Blender's cloth modifier (this
module imports bpy, so it runs inside `blender -b --python`) and written as a clothsim scene.

Strain is measured the same way on both peers where the caller asks for it: the largest (length - rest) / rest of
the grid's structural edges over the written frames, from the meshes themselves (Blender's evaluated mesh; the
OBJ files clothsim writes), rest lengths from the flat starting grid.
"""
import os
import time

import bpy
import numpy as np


def structural_strain(co, edges, rest):
    """Largest (length - rest) / rest over the grid's edges (its structural springs)."""
    d = co[edges[:, 1]] - co[edges[:, 0]]
    return float(np.max((np.linalg.norm(d, axis=1) - rest) / rest))


def grid_edges(side):
    """Structural edges of clothsim's row-major side x side grid (pins 0 and side - 1 are one edge's corners)."""
    idx = np.arange(side * side).reshape(side, side)
    along = np.stack([idx[:, :-1].ravel(), idx[:, 1:].ravel()], axis=1)
    across = np.stack([idx[:-1, :].ravel(), idx[1:, :].ravel()], axis=1)
    return np.concatenate([along, across])


def read_obj(path):
    """Vertex positions and triangles of an OBJ clothsim wrote."""
    verts, faces = [], []
    with open(path) as f:
        for line in f:
            if line.startswith("v "):
                verts.append(line.split()[1:4])
            elif line.startswith("f "):
                faces.append([int(t.split("/")[0]) - 1 for t in line.split()[1:4]])
    return np.array(verts, dtype=float), np.array(faces, dtype=np.int64)


def reset_scene(threads, fps, frames, gravity):
    """An empty Blender scene at `fps` over frames 1..1 + frames, with `threads` threads and this gravity."""
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj)
    # Each bake gets a fresh mesh: a removed object's cloth cache must not be read back by the next bake.
    for mesh in list(bpy.data.meshes):
        bpy.data.meshes.remove(mesh)
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.fps = fps
    scene.frame_start, scene.frame_end = 1, 1 + frames
    scene.gravity = gravity
    return scene


# Every damping setting of Blender's cloth at 0 (bench/peer_blender_motion.py and its test).
UNDAMPED = {name: 0.0 for name in ("air_damping", "tension_damping", "compression_damping", "shear_damping",
                                   "bending_damping")}


def matched_gravity(fps):
    """The scene gravity (m/s^2) under which Blender's cloth falls at 9.81 m/s^2: its solver counts time in frames
    and scales the scene's gravity by 0.001, so a sheet falls under 0.001 fps^2 times it."""
    return 9.81 / (0.001 * fps ** 2)


def backward_euler_fall(g, steps, step):
    """How far a free particle falls from rest in `steps` backward-Euler steps of `step` s under g: g h^2 n(n+1)/2."""
    return g * step * step * steps * (steps + 1) / 2


def bake_cloth(obj, pins, quality, tension, vertex_mass, frames, settings=None):
    """Gives obj a cloth modifier (the vertices `pins` pinned, tension = compression = shear, no collisions,
    `settings` overriding others by name), bakes it and returns the bake's wall and CPU seconds and the vertex
    positions of frames 2..1 + frames (one array each)."""
    scene = bpy.context.scene
    group = obj.vertex_groups.new(name="pins")
    group.add(pins, 1.0, "REPLACE")
    mod = obj.modifiers.new("Cloth", "CLOTH")
    s = mod.settings
    s.quality = quality
    s.mass = vertex_mass  # kg per vertex
    s.tension_stiffness = s.compression_stiffness = s.shear_stiffness = tension
    s.vertex_group_mass = "pins"
    for name, value in (settings or {}).items():
        setattr(s, name, value)
    mod.collision_settings.use_collision = False
    mod.collision_settings.use_self_collision = False
    mod.point_cache.frame_start, mod.point_cache.frame_end = 1, 1 + frames

    scene.frame_set(1)
    cpu0, wall0 = time.process_time(), time.perf_counter()
    bpy.ops.ptcache.bake_all(bake=True)
    wall, cpu = time.perf_counter() - wall0, time.process_time() - cpu0
    positions = []
    buf = np.empty(3 * len(obj.data.vertices))
    for f in range(2, 2 + frames):
        scene.frame_set(f)
        obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.vertices.foreach_get("co", buf)
        positions.append(buf.reshape(-1, 3).copy())
    bpy.ops.ptcache.free_bake_all()
    return wall, cpu, positions


def bake_blender(side, fps, frames, quality, tension, threads, settings=None, gravity=9.81, mass=1.0, pinned=True):
    """Bakes the sheet at `quality` substeps a frame; returns wall and CPU seconds of the bake, the largest
    structural strain over frames 2..1 + frames, whether every position stayed finite, and the mean drop of the
    vertices (m) at the last frame, which shows whether the sheet moved at all. `settings` overrides cloth
    settings by name (e.g. {"air_damping": 0.0}); without it Blender's defaults stand. `gravity` is the scene's
    (m/s^2, downwards), `mass` the sheet's (kg, spread evenly over its vertices); `pinned` False leaves the
    corners free (bench/peer_blender_motion.py)."""
    particles = side * side
    reset_scene(threads, fps, frames, (0, 0, -gravity))
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=side - 1, y_subdivisions=side - 1, size=1.0,
                                    location=(0, 0, 1))
    obj = bpy.context.object
    mesh = obj.data
    assert len(mesh.vertices) == particles, f"grid has {len(mesh.vertices)} vertices; expected {particles}"
    co = np.empty(3 * particles)
    mesh.vertices.foreach_get("co", co)
    co = co.reshape(-1, 3)
    # The two corners of the edge at the largest y, as clothsim's pins 0 and side - 1 are the corners of one edge.
    top = np.isclose(co[:, 1], co[:, 1].max())
    corners = [int(i) for i in np.flatnonzero(top & (np.isclose(co[:, 0], co[:, 0].min()) |
                                                     np.isclose(co[:, 0], co[:, 0].max())))]
    assert len(corners) == 2
    edges = np.empty(2 * len(mesh.edges), dtype=np.int64)
    mesh.edges.foreach_get("vertices", edges)
    edges = edges.reshape(-1, 2)
    rest = np.linalg.norm(co[edges[:, 1]] - co[edges[:, 0]], axis=1)

    wall, cpu, positions = bake_cloth(obj, corners if pinned else [], quality, tension, mass / particles, frames,
                                      settings)
    worst, finite = 0.0, True
    for pos in positions:
        finite = finite and bool(np.all(np.isfinite(pos)))
        worst = max(worst, structural_strain(pos, edges, rest))
    sag = float(np.mean(co[:, 2] - positions[-1][:, 2]))
    return dict(peer="blender", step=1.0 / (fps * quality), steps=frames * quality, wall=wall, cpu=cpu,
                max_strain=worst, finite=finite, sag=sag)


def write_clothsim_scene(xml, out, side, fps, frames, integrator, timestep, stiffness, cg_tolerance=1e-3,
                         max_strain=0.0, preconditioner="", newton_iterations=0, damping=0.1, air_damping=0.1,
                         bend=0.1):
    """The sheet as a clothsim scene (density 1 kg/m^2 over 1 m^2; air damping, spring damping and bend, a fraction
    of the stiffness, 0.1 unless given); the step is rounded to divide a frame evenly, as clothsim requires."""
    steps_per_frame = max(1, round(1.0 / (fps * timestep)))
    extra = f' preconditioner="{preconditioner}"' if preconditioner else ""
    extra += f' newtonIterations="{newton_iterations}"' if newton_iterations else ""
    limit = f' maxStrain="{max_strain!r}"' if max_strain > 0 else ""
    with open(xml, "w") as f:
        f.write(f"""<?xml version="1.0"?>
<!-- bench/peer_sheet.py: the peer sheet, {side} x {side}, 1 m, 1 kg, two corners pinned -->
<scene>
  <simulation timestep="{1.0 / (fps * steps_per_frame)!r}" fps="{fps}" startFrame="1" endFrame="{1 + frames}"
              integrator="{integrator}" cgTolerance="{cg_tolerance!r}" gravity="0 -9.81 0"{extra}/>
  <forces><airDamping value="{air_damping!r}"/></forces>
  <cloth name="sheet" grid="{side} {side}" size="1 1" translate="0 1 0" saveDir="{out}" saveName="sheet"{limit}>
    <density value="1"/>
    <stiffness value="{stiffness!r}" bend="{bend!r}"/>
    <damping value="{damping!r}"/>
    <pins vertices="0 {side - 1}"/>
  </cloth>
</scene>
""")
    return os.path.join(out, "sheet.{:04d}.obj")
