"""From the Blender scene to clothsim's files: one triangulated OBJ per cloth (world space, UVs per corner)
and the scene XML. Vertex order is kept, so clothsim's output vertex i is the Blender mesh's vertex i."""
import glob
import os
import re
import tempfile
from dataclasses import dataclass

import bpy

from . import collider_export, mesh_files, scene_xml
from .mesh_export import mesh_obj_text


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


def pinned_vertices(obj):
    s = obj.clothsim
    if not s.pin_group:
        return []
    group = obj.vertex_groups.get(s.pin_group)
    if group is None:
        raise ValueError(f"'{obj.name}': pin group '{s.pin_group}' is not a vertex group of this object")
    gi = group.index
    return [v.index for v in obj.data.vertices
            if any(g.group == gi and g.weight >= s.pin_weight for g in v.groups)]


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
        wind_strength=s.wind_strength, air_damping=s.air_damping, cloths=cloths)


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
        mesh_files.write_text_atomic(obj_path, mesh_obj_text(obj.data, obj.matrix_world, name))
        # Old frames, and temporary files of a run killed mid-write (clothsim writes NAME.obj.tmpPID, renames).
        prefix = os.path.join(glob.escape(frames_dir), glob.escape(name))
        for old in glob.glob(prefix + ".[0-9][0-9][0-9][0-9].obj") + glob.glob(prefix + ".[0-9][0-9][0-9][0-9].obj.tmp*"):
            os.remove(old)
        s = obj.clothsim
        specs.append(scene_xml.ClothSpec(
            name=name, obj=obj_path, save_dir=frames_dir, save_name=name, density=s.density,
            stiffness=s.stiffness, bend=s.bend, damping=s.damping, thickness=s.thickness, friction=s.friction,
            restitution=s.restitution, self_collision=s.self_collision, pins=pinned_vertices(obj)))
        exported.append(ExportedCloth(obj.name, frames_dir, name))
    if not specs:
        raise ValueError("no cloth in the scene: mark a mesh as Cloth in Properties > Physics > clothsim")
    spec = scene_spec(scene, specs)
    spec.colliders = collider_export.export_colliders(scene, work_dir, objects_of_role(scene, "COLLIDER"),
                                                      spec.start_frame, spec.end_frame)
    path = os.path.join(work_dir, "scene.xml")
    mesh_files.write_text_atomic(path, scene_xml.format_scene(spec))
    return ExportedScene(path, work_dir, spec.start_frame, spec.end_frame, exported)
