"""Headless test of the clothsim add-on against the real clothsim binary.

  blender -b --factory-startup --python-exit-code 1 --python test_addon.py -- CLOTHSIM_BIN SCRATCH_DIR

Builds a pinned plane and a sphere, marks them, runs Simulate, and checks that the cloth's evaluated vertex
positions at several frames equal clothsim's OBJ frames to float32 precision (what Blender stores), that the
pinned vertices did not move, that UVs and material survive, and that clothsim's own error messages (exit 2 and
exit 3) come back as operator reports; and that parameter maps baked from vertex groups, gusts, an external
force, implicit integration, maxStrain and clothCollision reach a scene clothsim accepts."""
import math
import os
import re
import shutil
import sys
import time

import bpy
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.dirname(HERE))  # tools/blender, which holds the clothsim_addon package

import addon_utils  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
BINARY, SCRATCH = os.path.abspath(argv[0]), os.path.abspath(argv[1])
addon_utils.enable("clothsim_addon", default_set=True, handle_error=None)
bpy.context.preferences.addons["clothsim_addon"].preferences.binary = BINARY

from clothsim_addon import mesh_files, runner  # noqa: E402
FAILURES = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILURES.append(what)


def evaluated_world_positions(obj):
    """Vertex positions after the modifier stack (the Mesh Cache modifier), in world space, float64."""
    dg = bpy.context.evaluated_depsgraph_get()
    mesh = obj.evaluated_get(dg).data
    co = np.empty(3 * len(mesh.vertices), dtype=np.float32)
    mesh.vertices.foreach_get("co", co)
    m = np.array(obj.matrix_world, dtype=np.float64)
    return co.reshape(-1, 3).astype(np.float64) @ m[:3, :3].T + m[:3, 3]


def build_scene():
    scene = bpy.context.scene
    for obj in list(scene.objects):
        bpy.data.objects.remove(obj)
    # A 1 m grid of 12 x 12 vertices, tilted and scaled so that world space differs from object space.
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=11, y_subdivisions=11, size=1.0, location=(0.1, -0.2, 1.2),
                                    rotation=(math.radians(20), 0, math.radians(10)))
    cloth = bpy.context.object
    cloth.name = "Sheet"
    cloth.scale = (1.5, 1.0, 1.0)
    # Pins: the two corners of one edge, found by position so the test does not depend on Blender's numbering.
    co = np.array([v.co[:] for v in cloth.data.vertices])
    corners = [int(np.argmin(np.abs(co[:, 0] - co[:, 0].min()) + np.abs(co[:, 1] - y))) for y in
               (co[:, 1].min(), co[:, 1].max())]
    group = cloth.vertex_groups.new(name="pins")
    group.add(corners, 1.0, "REPLACE")
    group.add([int(np.argmin(np.abs(co[:, 0]) + np.abs(co[:, 1])))], 0.2, "REPLACE")  # under the pin weight
    # A modifier already on the object: the simulation must go under it, first in the stack.
    subsurf = cloth.modifiers.new("Subdivision", "SUBSURF")
    subsurf.levels = subsurf.render_levels = 0
    material = bpy.data.materials.new("Checker")
    cloth.data.materials.append(material)
    s = cloth.clothsim
    s.role = "CLOTH"
    s.density, s.stiffness, s.bend, s.damping, s.thickness = 0.2, 400.0, 0.2, 0.05, 0.004
    s.pin_group = "pins"

    bpy.ops.mesh.primitive_uv_sphere_add(radius=0.3, location=(0, 0, 0.4))
    sphere = bpy.context.object
    sphere.name = "Ball"
    sphere.clothsim.role = "COLLIDER"  # a mesh collider at first, out of the sheet's way

    scene.frame_start, scene.frame_end = 1, 12
    scene.render.fps, scene.render.fps_base = 24, 1.0
    run = scene.clothsim
    run.integrator = "symplectic"
    run.timestep = 0.001
    run.threads = 2
    run.wind_velocity, run.wind_strength, run.air_damping = (0.5, 0.0, 0.0), 0.1, 0.05
    run.cache_dir = os.path.join(SCRATCH, "cache")
    return cloth, sphere, corners


def test_simulate(cloth, corners):
    world0 = evaluated_world_positions(cloth)
    uv0 = np.array([d.uv[:] for d in cloth.data.uv_layers.active.data])
    result = bpy.ops.clothsim.simulate()
    check(result == {"FINISHED"}, f"Simulate finished ({result})")
    frames_dir = os.path.join(SCRATCH, "cache", "frames")
    files = sorted(f for f in os.listdir(frames_dir) if f.startswith("Sheet."))
    check(len(files) == 12, f"clothsim wrote 12 frames of the sheet ({len(files)})")
    check(cloth.modifiers[0].type == "MESH_CACHE", "the result plays through a Mesh Cache modifier, first in the stack")

    # Frame 1 is the exported mesh itself: the OBJ export kept vertex order and world positions.
    first = mesh_files.read_obj_positions(mesh_files.frame_path(frames_dir, "Sheet", 1))
    err0 = np.abs(first - world0).max()
    check(err0 < 1e-6, f"frame 1 equals the Blender mesh in world space (max error {err0:.2e} m)")

    moved = 0.0
    for f in (1, 4, 8, 12):
        bpy.context.scene.frame_set(f)
        got = evaluated_world_positions(cloth)
        want = mesh_files.read_obj_positions(mesh_files.frame_path(frames_dir, "Sheet", f))
        # Blender keeps float32 object-space coordinates: a few ulps of ~2 m after the transform.
        err = np.abs(got - want).max()
        check(err < 1e-6, f"frame {f}: Blender vertices equal clothsim's OBJ (max error {err:.2e} m)")
        pin_err = np.abs(got[corners] - world0[corners]).max()
        check(pin_err < 1e-6, f"frame {f}: pinned vertices {corners} did not move ({pin_err:.2e} m)")
        moved = max(moved, np.linalg.norm(got - world0, axis=1).max())
    # Free fall over 11/24 s alone would be g t^2 / 2 = 1.03 m; the pins hold the sheet, so well over 5 cm.
    check(moved > 0.05, f"the unpinned vertices moved ({moved:.3f} m), so the comparisons above are not vacuous")

    dg = bpy.context.evaluated_depsgraph_get()
    mesh = cloth.evaluated_get(dg).data
    uv = np.array([d.uv[:] for d in mesh.uv_layers.active.data])
    check(uv.shape == uv0.shape and np.array_equal(uv, uv0), "UVs kept")
    check(mesh.materials[0] is not None and mesh.materials[0].name == "Checker", "material kept")

    # Load Result brings the same frames back from the cache folder, without simulating.
    cloth.modifiers.remove(cloth.modifiers["clothsim"])
    check(bpy.ops.clothsim.load() == {"FINISHED"}, "Load Result")
    bpy.context.scene.frame_set(8)
    want = mesh_files.read_obj_positions(mesh_files.frame_path(frames_dir, "Sheet", 8))
    err = np.abs(evaluated_world_positions(cloth) - want).max()
    check(cloth.modifiers[0].name == "clothsim" and err < 1e-6, f"Load Result: frame 8 again ({err:.2e} m)")

    # The scene has the pins of weight >= 0.5 only.
    text = open(os.path.join(SCRATCH, "cache", "scene.xml")).read()
    check(f'<pins vertices="{corners[0]} {corners[1]}"/>' in text, "pins exported from the vertex group")
    for element in ('<density value="0.2"/>', '<stiffness value="400" bend="0.2"/>', '<thickness value="0.004"/>',
                    'gravity="0 0 -9.81"', '<wind velocity="0.5 0 0" strength="0.1"/>', '<airDamping value="0.05"/>'):
        check(element in text, f"scene has {element}")


def expect_error(what, needle):
    try:
        bpy.ops.clothsim.simulate()
    except RuntimeError as e:
        msg = str(e)
        check(needle in msg, f"{what}: report carries clothsim's message ({msg.strip()!r})")
        return
    check(False, f"{what}: Simulate reported no error")


def test_errors(cloth, sphere):
    scene = bpy.context.scene
    scene.clothsim.use_scene_range = False
    scene.clothsim.frame_start, scene.clothsim.frame_end = 10, 5
    expect_error("bad frame range (exit 2)", "startFrame 10 is after endFrame 5")
    scene.clothsim.use_scene_range = True
    stiffness, timestep = cloth.clothsim.stiffness, scene.clothsim.timestep
    # Without the collider: a cloth blown up to 1e30 m is a divergence test, not a broad-phase test.
    cloth.clothsim.stiffness, scene.clothsim.timestep, sphere.clothsim.role = 1e9, 0.01, "NONE"
    expect_error("divergence (exit 3)", "diverged")
    cloth.clothsim.stiffness, scene.clothsim.timestep, sphere.clothsim.role = stiffness, timestep, "COLLIDER"


def test_cancel(cloth):
    """The background job reports progress from clothsim's stderr and stops on cancel, leaving whole frames."""
    scene = bpy.context.scene
    scene.frame_end, scene.clothsim.timestep = 2000, 0.0001  # some 10 s of work: cancelled long before
    check(bpy.ops.clothsim.write_scene() == {"FINISHED"}, "Write Scene")
    job = runner.ClothsimJob(BINARY, os.path.join(SCRATCH, "cache", "scene.xml"), threads=1)
    while job.poll() is None and job.progress()[0] < 2:
        time.sleep(0.01)
    done, total = job.progress()
    check(total == 2000 and done >= 2, f"progress read from clothsim's stderr ({done}/{total})")
    job.cancel()
    check(job.poll() not in (None, 0), f"cancel stopped clothsim (exit {job.poll()})")
    frames_dir = os.path.join(SCRATCH, "cache", "frames")
    written = sorted(f for f in os.listdir(frames_dir) if f.startswith("Sheet.") and f.endswith(".obj"))
    check(2 <= len(written) < 2000, f"cancelled early ({len(written)} frames written)")
    sizes = {len(mesh_files.read_obj_positions(os.path.join(frames_dir, f))) for f in written}
    check(sizes == {len(cloth.data.vertices)}, f"every frame left is whole ({sizes} vertices)")
    scene.frame_end, scene.clothsim.timestep = 12, 0.001


def test_colliders(cloth, sphere):
    """Colliders: an exact sphere the sheet falls onto, a plane, a static mesh written from its evaluated
    (subdivided) shape and an animated mesh written frame by frame."""
    scene = bpy.context.scene
    cloth.clothsim.pin_group = ""
    cloth.modifiers.remove(cloth.modifiers["clothsim"])  # it plays the diverged run: back to the mesh as built
    centre = evaluated_world_positions(cloth).mean(axis=0)
    sphere.location = centre - np.array([0.0, 0.0, 0.55])
    sphere.clothsim.collider_shape = "SPHERE"

    bpy.ops.mesh.primitive_plane_add(size=2, location=(0, 0, -1), rotation=(math.radians(30), 0, 0))
    ground = bpy.context.object
    ground.clothsim.role, ground.clothsim.collider_shape = "COLLIDER", "PLANE"
    bpy.ops.mesh.primitive_cube_add(size=0.2, location=(3, 0, 0))
    rock = bpy.context.object
    rock.name = "Rock"
    rock.modifiers.new("Subdivision", "SUBSURF").levels = 1
    rock.clothsim.role = "COLLIDER"
    bpy.ops.mesh.primitive_cube_add(size=0.2, location=(-3, 0, 0))
    box = bpy.context.object
    box.name = "Box"
    box.clothsim.role, box.clothsim.collider_animated = "COLLIDER", True
    box.keyframe_insert("location", frame=1)
    box.location = (-3, 1, 0)
    box.keyframe_insert("location", frame=12)

    check(bpy.ops.clothsim.simulate() == {"FINISHED"}, "Simulate with colliders")
    text = open(os.path.join(SCRATCH, "cache", "scene.xml")).read()
    r = sphere.dimensions[0] / 2
    m = re.search(r'<sphere name="Ball" center="([^"]*)" radius="([^"]*)"', text)
    got = np.array(m.group(1).split(), dtype=float) if m else np.zeros(3)
    check(m is not None and np.abs(got - np.array(sphere.location)).max() < 1e-6 and float(m.group(2)) == 0.3,
          f"sphere: centre from the object, radius from its dimensions ({m and m.group(0)})")
    check('<plane name="Plane" point="0 0 -1" normal="0 -0.5 0.8660254" friction="0.3"/>' in text,
          "plane: its local +Z turned 30 degrees about X")

    # The sheet fell onto the ball: nothing inside it, and some of it resting within a few thickness of it.
    bpy.context.scene.frame_set(12)
    dist = np.linalg.norm(evaluated_world_positions(cloth) - np.array(sphere.location), axis=1)
    check(dist.min() > r - 0.001, f"no cloth vertex inside the sphere (closest {dist.min():.4f} m, radius {r:.4f})")
    check(dist.min() < r + 0.02, f"the cloth reached the sphere (closest {dist.min():.4f} m)")

    colliders = os.path.join(SCRATCH, "cache", "colliders")
    dg = bpy.context.evaluated_depsgraph_get()
    subdivided = rock.evaluated_get(dg).data
    got = mesh_files.read_obj_positions(os.path.join(colliders, "Rock.obj"))
    check(len(got) == len(subdivided.vertices) == 26, f"static mesh: the evaluated (subdivided) mesh ({len(got)} vertices)")
    for f in (1, 6, 12):
        scene.frame_set(f)
        got = mesh_files.read_obj_positions(mesh_files.frame_path(colliders, "Box", f))
        err = np.abs(got - evaluated_world_positions(box)).max()
        check(err < 1e-6, f"animated mesh: frame {f} written where Blender has it ({err:.1e} m)")
    check('sequence="' + os.path.join(colliders, "Box.####.obj") + '"' in text, "animated mesh: a <static sequence>")


def read_png_grey16(path):
    """The 16-bit grey PNGs the add-on bakes (filter 0 on every row), as an (h, w) array of 0..1."""
    import struct
    import zlib
    data = open(path, "rb").read()
    pos, idat, w, h = 8, b"", 0, 0
    while pos < len(data):
        n, tag = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if tag == b"IHDR":
            w, h = struct.unpack(">II", body[:8])
        elif tag == b"IDAT":
            idat += body
        pos += 12 + n
    rows = np.frombuffer(zlib.decompress(idat), dtype=np.uint8).reshape(h, 1 + 2 * w)
    return rows[:, 1:].copy().view(">u2").astype(np.float64) / 65535


def sample(grey, u, v):
    """docs/maps.md: texel (i, j) centred at u = (i + 0.5)/W, v = 1 - (j + 0.5)/H, bilinear between, clamped."""
    h, w = grey.shape
    x, y = u * w - 0.5, (1 - v) * h - 0.5
    i, j = int(np.floor(x)), int(np.floor(y))
    fx, fy = x - i, y - j
    at = lambda a, b: grey[min(max(b, 0), h - 1), min(max(a, 0), w - 1)]  # noqa: E731
    return ((1 - fx) * (1 - fy) * at(i, j) + fx * (1 - fy) * at(i + 1, j) + (1 - fx) * fy * at(i, j + 1)
            + fx * fy * at(i + 1, j + 1))


def test_scene_format(cloth):
    """Parameter maps from vertex groups, gusts, external force, implicit integration, maxStrain and
    clothCollision reach the scene; clothsim accepts it and runs it."""
    import subprocess
    scene, s = bpy.context.scene, cloth.clothsim
    cloth.modifiers.remove(cloth.modifiers["clothsim"])
    co = np.array([v.co[:] for v in cloth.data.vertices])
    ramp = (co[:, 0] - co[:, 0].min()) / np.ptp(co[:, 0])  # 0 at one edge, 1 at the other
    for name in ("stiff", "thick", "heavy"):
        group = cloth.vertex_groups.new(name=name)
        for i, w in enumerate(ramp):
            if i % 5:  # every fifth vertex outside the group: weight 0
                group.add([i], float(w), "REPLACE")
    s.stiffness_group, s.stiffness, s.stiffness_max = "stiff", 200.0, 800.0
    s.thickness_group, s.thickness, s.thickness_max = "thick", 0.002, 0.008
    s.mass_group, s.mass_min, s.mass_max = "heavy", 0.001, 0.004
    s.max_strain, s.cloth_collision = 0.1, False
    run = scene.clothsim
    run.integrator, run.timestep, run.cloth_collision = "implicit", 1 / 240, False
    run.random_amplitude, run.random_seed, run.random_period, run.random_cell_size = 1.5, 3, 0.25, 0.3
    run.external_acceleration = (0.5, 0.0, 0.0)
    check(bpy.ops.clothsim.write_scene() == {"FINISHED"}, "Write Scene with maps and forces")
    cache = os.path.join(SCRATCH, "cache")
    text = open(os.path.join(cache, "scene.xml")).read()
    maps = os.path.join(cache, "maps")
    for element in ('integrator="implicit"', 'clothCollision="false" maxStrain="0.1"',
                    '<simulation timestep="0.004166667"', 'clothCollision="false"/>',
                    '<external acceleration="0.5 0 0"/>',
                    '<random amplitude="1.5" seed="3" period="0.25" cellSize="0.3"/>',
                    f'<stiffness min="200" max="800" map="{os.path.join(maps, "Sheet_stiffness.png")}" bend="0.2"/>',
                    f'<thickness min="0.002" max="0.008" map="{os.path.join(maps, "Sheet_thickness.png")}"/>',
                    f'<mass min="0.001" max="0.004" map="{os.path.join(maps, "Sheet_mass.png")}"/>'):
        check(element in text, f"scene has {element}")
    check("<density" not in text, "a mass map replaces the density")
    # Every vertex's map sample, at each of its UVs, is its group weight (0 outside the group).
    mesh = cloth.data
    uv = np.array([d.uv[:] for d in mesh.uv_layers.active.data], dtype=np.float32).astype(np.float64)
    corner_vertex = [loop.vertex_index for loop in mesh.loops]
    want = np.where(np.arange(len(ramp)) % 5 != 0, ramp.astype(np.float32), 0.0)
    for element in ("stiffness", "thickness", "mass"):
        grey = read_png_grey16(os.path.join(maps, f"Sheet_{element}.png"))
        err = max(abs(sample(grey, *uv[c]) - want[vi]) for c, vi in enumerate(corner_vertex))
        check(err < 2e-5, f"{element} map: each vertex's UV samples its weight (max error {err:.1e})")
    r = subprocess.run([BINARY, "validate", os.path.join(cache, "scene.xml")], capture_output=True, text=True)
    mapped = r"stiffness (per element|\d+ values) \(mapped or scaled\).*thickness (per element|\d+ values) \(mapped"
    check(r.returncode == 0 and re.search(mapped, r.stdout) is not None,
          f"clothsim validate takes the maps ({r.stdout!r})")
    check(bpy.ops.clothsim.simulate() == {"FINISHED"}, "Simulate the implicit, strain-limited, gusty sheet")


def test_stitches(cloth):
    """A loose edge (Blender's sewing edge) reaches clothsim as a stitch record that it reads and counts."""
    import bmesh
    import subprocess
    bm = bmesh.new()
    bm.from_mesh(cloth.data)
    bm.verts.ensure_lookup_table()
    bm.edges.new((bm.verts[0], bm.verts[11]))  # the two ends of the grid's first row: not yet joined
    bm.to_mesh(cloth.data)
    bm.free()
    check(bpy.ops.clothsim.write_scene() == {"FINISHED"}, "Write Scene with a sewing edge")
    cache = os.path.join(SCRATCH, "cache")
    text = open(os.path.join(cache, "Sheet.obj")).read()
    check(re.findall(r"^stitch .*$", text, re.M) == ["stitch 0 11 11 0"], "the loose edge is one stitch record")
    r = subprocess.run([BINARY, "validate", os.path.join(cache, "scene.xml")], capture_output=True, text=True)
    check(r.returncode == 0 and "stitches 1" in r.stdout, f"clothsim validate counts the stitch ({r.stdout!r})")


def main():
    shutil.rmtree(SCRATCH, ignore_errors=True)
    os.makedirs(SCRATCH)
    cloth, _sphere, corners = build_scene()
    test_simulate(cloth, corners)
    test_errors(cloth, _sphere)
    test_cancel(cloth)
    test_colliders(cloth, _sphere)
    test_scene_format(cloth)
    test_stitches(cloth)
    print(f"{len(FAILURES)} failure(s)")
    sys.exit(1 if FAILURES else 0)


main()
