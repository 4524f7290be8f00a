"""Playback cost of a simulated sequence on a large mesh: the Mesh Cache (PC2) the add-on uses against a
frame-change handler that parses each frame's OBJ into the mesh, the alternative it was chosen over.

  blender -b --factory-startup --python tools/blender/bench_playback.py -- N FRAMES SCRATCH_DIR

Writes FRAMES synthetic OBJ frames of an N x N grid (what clothsim writes: v, vt, vn, f lines), then times
scene.frame_set over all frames with each method, three rounds, and prints the median per frame."""
import os
import statistics
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_utils  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
N, FRAMES, OUT = int(argv[0]), int(argv[1]), os.path.abspath(argv[2])
addon_utils.enable("clothsim_addon", default_set=True, handle_error=None)
from clothsim_addon import mesh_files, result  # noqa: E402

os.makedirs(OUT, exist_ok=True)
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
bpy.ops.mesh.primitive_grid_add(x_subdivisions=N - 1, y_subdivisions=N - 1, size=1.0)
obj = bpy.context.object
mesh = obj.data
n = len(mesh.vertices)
co = np.empty(3 * n)
mesh.vertices.foreach_get("co", co)
co = co.reshape(-1, 3)
mesh.calc_loop_triangles()
tris = np.empty(3 * len(mesh.loop_triangles), dtype=np.int64)
mesh.loop_triangles.foreach_get("vertices", tris)
tris = tris.reshape(-1, 3)
for f in range(1, FRAMES + 1):
    p = co + np.array([0, 0, -0.01 * f]) + 0.01 * np.sin(co * f)
    text = mesh_files.format_obj("sheet", p, tris)
    mesh_files.write_text_atomic(mesh_files.frame_path(OUT, "sheet", f), text)

t0 = time.perf_counter()
result.load_result(obj, OUT, "sheet", 1, FRAMES, OUT)
load_s = time.perf_counter() - t0


def play():
    times = []
    for _round in range(3):
        t = time.perf_counter()
        for f in range(1, FRAMES + 1):
            bpy.context.scene.frame_set(f)
            obj.evaluated_get(bpy.context.evaluated_depsgraph_get()).data.vertices[0].co
        times.append((time.perf_counter() - t) / FRAMES)
    return statistics.median(times)


cache_s = play()
obj.modifiers.remove(obj.modifiers["clothsim"])


def handler(scene, _depsgraph=None):
    p = mesh_files.read_obj_positions(mesh_files.frame_path(OUT, "sheet", scene.frame_current))
    mesh.vertices.foreach_set("co", p.astype(np.float32).ravel())
    mesh.update()


bpy.app.handlers.frame_change_pre.append(handler)
handler_s = play()
bpy.app.handlers.frame_change_pre.remove(handler)
print(f"bench_playback: {n} vertices, {FRAMES} frames: import into PC2 {load_s:.2f} s once; per frame: "
      f"Mesh Cache {cache_s * 1e3:.1f} ms, OBJ handler {handler_s * 1e3:.1f} ms, ratio {handler_s / cache_s:.1f}")
