"""Brings clothsim's OBJ frames back as a PC2 point cache played by Blender's Mesh Cache modifier.

Why a point cache and not a frame-change handler or shape keys: the modifier is C code that seeks to one
frame of the file on each evaluation, so playback costs one read of n*12 bytes per frame whatever the sequence
length; the mesh itself (UVs, materials, vertex groups, later modifiers) is untouched; nothing of the sequence
goes into the .blend; and it plays in renders and on machines without the add-on. Shape keys store every frame
in the .blend and Blender walks the key list on each evaluation; a Python handler parses an OBJ per frame
change and does not run where the add-on is absent."""
import os

import bpy
import numpy as np

from . import mesh_files

MODIFIER_NAME = "clothsim"


def read_frames(save_dir, save_name, start, end):
    """Positions of the frames start.. that exist, in order, stopping at the first missing one (a cancelled or
    diverged run leaves only whole frames, a prefix of the sequence)."""
    frames = []
    for f in range(start, end + 1):
        path = mesh_files.frame_path(save_dir, save_name, f)
        if not os.path.exists(path):
            break
        frames.append(mesh_files.read_obj_positions(path))
    return frames


def attach_cache(obj, frames, start, cache_path):
    """Writes the frames (world space) as object-space PC2 and points the object's Mesh Cache modifier at it."""
    n = len(obj.data.vertices)
    for k, p in enumerate(frames):
        if p.shape[0] != n:
            raise ValueError(f"'{obj.name}': frame {start + k} has {p.shape[0]} vertices but the mesh has {n}; "
                             "was the mesh edited after Simulate?")
    inv = np.linalg.inv(np.array(obj.matrix_world, dtype=np.float64))
    local = np.stack(frames) @ inv[:3, :3].T + inv[:3, 3]
    mesh_files.write_pc2(cache_path, local, start)

    mod = obj.modifiers.get(MODIFIER_NAME)
    if mod is None or mod.type != "MESH_CACHE":
        mod = obj.modifiers.new(MODIFIER_NAME, "MESH_CACHE")
    mod.cache_format = "PC2"
    mod.filepath = cache_path
    mod.time_mode = "FRAME"
    mod.play_mode = "SCENE"
    mod.frame_start = float(start)   # scene frame `start` plays the cache's first sample
    mod.frame_scale = 1.0
    mod.forward_axis = "POS_Y"       # identity: the cache is already in Blender's object space
    mod.up_axis = "POS_Z"
    mod.deform_mode = "OVERWRITE"
    mod.interpolation = "NONE"
    # First in the stack: the simulation replaces the base mesh, later modifiers (subdivision) act on it.
    if obj.modifiers[0] != mod:
        with bpy.context.temp_override(object=obj, active_object=obj):
            bpy.ops.object.modifier_move_to_index(modifier=mod.name, index=0)
    obj.update_tag()


def load_result(obj, save_dir, save_name, start, end, work_dir):
    frames = read_frames(save_dir, save_name, start, end)
    if not frames:
        return 0
    attach_cache(obj, frames, start, os.path.join(work_dir, save_name + ".pc2"))
    return len(frames)
