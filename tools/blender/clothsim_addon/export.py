"""From the Blender scene to clothsim's files: one triangulated OBJ per cloth (world space, UVs per corner)
and the scene XML. Vertex order is kept, so clothsim's output vertex i is the Blender mesh's vertex i."""
import glob
import os
import re
import tempfile
from dataclasses import dataclass

import bpy

import numpy as np

from . import collider_export, map_bake, mesh_files, scene_xml
from .mesh_export import mesh_obj_text

# Vertex groups baked into maps: (scene element, group property, value at weight 0, value at weight 1).
MAPPED_PARAMETERS = (("stiffness", "stiffness_group", "stiffness", "stiffness_max"),
                     ("thickness", "thickness_group", "thickness", "thickness_max"),
                     ("mass", "mass_group", "mass_min", "mass_max"))


@dataclass
class ExportedCloth:
    object_name: str
    save_dir: str
    save_name: str


@dataclass
class ExportedScene:
    path: str
    work_dir: str
    start_frame: int
    end_frame: int
    cloths: list


def work_dir_of(scene):
    path = scene.clothsim.cache_dir
    if path.startswith("//") and not bpy.data.filepath:
        return os.path.join(tempfile.gettempdir(), "clothsim_" + re.sub(r"\W", "_", scene.name))
    return os.path.abspath(bpy.path.abspath(path))


def frames_dir_of(work_dir):
    return os.path.join(work_dir, "frames")


def safe_name(name, taken):
    base = re.sub(r"[^A-Za-z0-9_.-]", "_", name) or "cloth"
    out, k = base, 1
    while out in taken:
        k += 1
        out = f"{base}_{k}"
    taken.add(out)
    return out


def objects_of_role(scene, role):
    """(object, file name) of every mesh of a role, in a fixed order, so that Load Result finds the same files."""
    taken = set()
    return [(obj, safe_name(obj.name, taken)) for obj in scene.objects
            if obj.type == "MESH" and obj.clothsim.role == role]


def cloth_objects(scene):
    return objects_of_role(scene, "CLOTH")


def vertex_group_weights(obj, group_name, what):
    """Weight of every vertex in the named group (None for a vertex outside it)."""
    group = obj.vertex_groups.get(group_name)
    if group is None:
        raise ValueError(f"'{obj.name}': {what} group '{group_name}' is not a vertex group of this object")
    gi = group.index
    weights = [None] * len(obj.data.vertices)
    for v in obj.data.vertices:
        for g in v.groups:
            if g.group == gi:
                weights[v.index] = g.weight
    return weights


def pinned_vertices(obj):
    s = obj.clothsim
    if not s.pin_group:
        return []
    weights = vertex_group_weights(obj, s.pin_group, "pin")
    return [i for i, w in enumerate(weights) if w is not None and w >= s.pin_weight]


def parameter_maps(obj, maps_dir, name):
    """Bakes each parameter's vertex group into maps_dir/<name>_<element>.png: {element: (min, max, path)}."""
    s, mesh, out = obj.clothsim, obj.data, {}
    for element, group_prop, lo_prop, hi_prop in MAPPED_PARAMETERS:
        group = getattr(s, group_prop)
        if not group:
            continue
        if mesh.uv_layers.active is None:
            raise ValueError(f"'{obj.name}': the {element} group needs a UV map (clothsim samples maps at UVs)")
        weights = np.array([w or 0.0 for w in vertex_group_weights(obj, group, element)])
        corner_vertex = np.empty(len(mesh.loops), dtype=np.int64)
        mesh.loops.foreach_get("vertex_index", corner_vertex)
        uv = np.empty(2 * len(mesh.loops), dtype=np.float32)  # Blender's own precision, as the OBJ writes it
        mesh.uv_layers.active.data.foreach_get("uv", uv)
        os.makedirs(maps_dir, exist_ok=True)
        path = os.path.join(maps_dir, f"{name}_{element}.png")
        map_bake.bake_weights(path, weights, corner_vertex, uv.reshape(-1, 2).astype(np.float64))
        out[element] = (getattr(s, lo_prop), getattr(s, hi_prop), path)
    return out


def frame_range(scene):
    s = scene.clothsim
    if s.use_scene_range:
        return scene.frame_start, scene.frame_end
    return s.frame_start, s.frame_end


def scene_spec(scene, cloths):
    s = scene.clothsim
    start, end = frame_range(scene)
    gravity = tuple(scene.gravity) if s.use_scene_gravity else tuple(s.gravity)
    return scene_xml.SceneSpec(
        timestep=s.timestep, fps=scene.render.fps / scene.render.fps_base, start_frame=start, end_frame=end,
        integrator=s.integrator, gravity=gravity, wind_velocity=tuple(s.wind_velocity),
        wind_strength=s.wind_strength, air_damping=s.air_damping,
        external_acceleration=tuple(s.external_acceleration), random_amplitude=s.random_amplitude,
        random_seed=s.random_seed, random_period=s.random_period, random_cell_size=s.random_cell_size,
        cloth_collision=s.cloth_collision, cloths=cloths)


def export_scene(scene):
    """Writes <cache>/scene.xml and a mesh per cloth; removes the cloth's old frames so none is mistaken for a
    result of this run."""
    work_dir = work_dir_of(scene)
    frames_dir = frames_dir_of(work_dir)
    os.makedirs(frames_dir, exist_ok=True)
    specs, exported = [], []
    for obj, name in cloth_objects(scene):
        obj_path = os.path.join(work_dir, name + ".obj")
        # The base mesh, before modifiers: the Mesh Cache with the result goes first in the stack.
        mesh_files.write_text_atomic(obj_path, mesh_obj_text(obj.data, obj.matrix_world, name, with_stitches=True))
        # Old frames, and temporary files of a run killed mid-write (clothsim writes NAME.obj.tmpPID, renames).
        prefix = os.path.join(glob.escape(frames_dir), glob.escape(name))
        for old in glob.glob(prefix + ".[0-9][0-9][0-9][0-9].obj") + glob.glob(prefix + ".[0-9][0-9][0-9][0-9].obj.tmp*"):
            os.remove(old)
        s = obj.clothsim
        specs.append(scene_xml.ClothSpec(
            name=name, obj=obj_path, save_dir=frames_dir, save_name=name, density=s.density,
            stiffness=s.stiffness, bend=s.bend, damping=s.damping, thickness=s.thickness, friction=s.friction,
            restitution=s.restitution, self_collision=s.self_collision, cloth_collision=s.cloth_collision,
            max_strain=s.max_strain, pins=pinned_vertices(obj),
            maps=parameter_maps(obj, os.path.join(work_dir, "maps"), name)))
        exported.append(ExportedCloth(obj.name, frames_dir, name))
    if not specs:
        raise ValueError("no cloth in the scene: mark a mesh as Cloth in Properties > Physics > clothsim")
    spec = scene_spec(scene, specs)
    spec.colliders = collider_export.export_colliders(scene, work_dir, objects_of_role(scene, "COLLIDER"),
                                                      spec.start_frame, spec.end_frame)
    path = os.path.join(work_dir, "scene.xml")
    mesh_files.write_text_atomic(path, scene_xml.format_scene(spec))
    return ExportedScene(path, work_dir, spec.start_frame, spec.end_frame, exported)
