"""Mesh files on the way out (triangulated OBJ with UVs) and on the way back (clothsim's OBJ frames to one
PC2 point cache). No bpy here: callers pass numpy arrays, so the formats can be checked without Blender.
"""
import os
import struct

import numpy as np


def format_obj(name, positions, tri_vertices, tri_uv_index=None, uvs=None, stitches=()):
    """OBJ text: positions (n, 3) float, tri_vertices (t, 3) int from 0; optional uvs (m, 2) and
    tri_uv_index (t, 3) into them. Vertex order is kept, so clothsim's particle i is Blender's vertex i.
    stitches: (i, j) vertex pairs sewn together, written as Codim-IPC stitch records `stitch i j j 0` (vertex i
    belongs at vertex j; docs/garments.md)."""
    lines = [f"# clothsim add-on export\no {name}"]
    # 9 significant digits read back to the same float32, which is what Blender stores.
    lines += [f"v {x:.9g} {y:.9g} {z:.9g}" for x, y, z in np.asarray(positions, dtype=np.float64)]
    t = np.asarray(tri_vertices, dtype=np.int64) + 1
    if uvs is not None and tri_uv_index is not None and len(uvs):
        lines += [f"vt {u:.9g} {v:.9g}" for u, v in np.asarray(uvs, dtype=np.float64)]
        tu = np.asarray(tri_uv_index, dtype=np.int64) + 1
        lines += [f"f {a}/{ta} {b}/{tb} {c}/{tc}" for (a, b, c), (ta, tb, tc) in zip(t.tolist(), tu.tolist())]
    else:
        lines += [f"f {a} {b} {c}" for a, b, c in t.tolist()]
    lines += [f"stitch {i} {j} {j} 0" for i, j in stitches]
    return "\n".join(lines) + "\n"


def write_text_atomic(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def read_obj_positions(path):
    """The 'v' lines of an OBJ file as an (n, 3) float64 array, in file order."""
    with open(path, "r", encoding="utf-8") as f:
        coords = [line[2:] for line in f if line.startswith("v ")]
    if not coords:
        return np.zeros((0, 3))
    flat = np.array(" ".join(coords).split(), dtype=np.float64)
    if flat.size != 3 * len(coords):
        raise ValueError(f"{path}: expected three numbers on every 'v' line")
    return flat.reshape(-1, 3)


def frame_path(save_dir, save_name, frame):
    """Same name as clothsim's io::frame_path: <saveDir>/<saveName>.<NNNN>.obj."""
    return os.path.join(save_dir, f"{save_name}.{frame:04d}.obj")


PC2_HEADER = struct.Struct("<12siiffi")  # magic, version, points, start frame, sample rate, samples


def write_pc2(path, frames, start_frame):
    """frames: (samples, points, 3) positions in object space. PC2 is the point-cache format Blender's Mesh
    Cache modifier streams from disk, one frame at a time."""
    with np.errstate(over="ignore"):  # the last frames before a divergence may exceed float32: inf, as they are
        frames = np.ascontiguousarray(frames, dtype="<f4")
    samples, points, _ = frames.shape
    tmp = path + ".tmp"
    with open(tmp, "wb") as f:
        f.write(PC2_HEADER.pack(b"POINTCACHE2\0", 1, points, float(start_frame), 1.0, samples))
        f.write(frames.tobytes())
    os.replace(tmp, path)

