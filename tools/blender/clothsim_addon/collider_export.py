"""Colliders: <static obj>, <static sequence> (animated: one OBJ per frame from the evaluated mesh, so
keyframes, armatures and deforming modifiers all count), <sphere> and <plane>, all in world space."""
import glob
import os

import bpy
import numpy as np

from . import mesh_files, scene_xml
from .mesh_export import mesh_obj_text


def sphere_of(obj):
    """Centre: the object's origin; radius: half its largest world-space dimension (a UV sphere's radius)."""
    return tuple(obj.matrix_world.translation), max(obj.dimensions) / 2


def plane_of(obj):
    """A point (the origin) and the normal (the object's local +Z in world space): Blender's Plane faces +Z."""
    m = np.array(obj.matrix_world, dtype=np.float64)
    normal = np.linalg.inv(m[:3, :3]).T @ np.array([0.0, 0.0, 1.0])  # normals transform by the inverse transpose
    return tuple(m[:3, 3]), tuple(normal / np.linalg.norm(normal))


def evaluated_obj_text(obj, name, depsgraph):
    evaluated = obj.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    try:
        return mesh_obj_text(mesh, evaluated.matrix_world, name, with_uvs=False)
    finally:
        evaluated.to_mesh_clear()


def export_colliders(scene, work_dir, names, start, end):
    """names: (object, file name) of the colliders. Writes their meshes under <work_dir>/colliders and returns
    their ColliderSpecs."""
    out_dir = os.path.join(work_dir, "colliders")
    os.makedirs(out_dir, exist_ok=True)
    specs, animated = [], []
    for obj, name in names:
        s = obj.clothsim
        spec = scene_xml.ColliderSpec(kind=s.collider_shape.lower(), name=name, friction=s.friction)
        if s.collider_shape == "SPHERE":
            spec.center, spec.radius = sphere_of(obj)
        elif s.collider_shape == "PLANE":
            spec.point, spec.normal = plane_of(obj)
        elif s.collider_animated:
            spec.kind, spec.sequence = "static", os.path.join(out_dir, name + ".####.obj")
            for old in glob.glob(os.path.join(glob.escape(out_dir), glob.escape(name) + ".[0-9][0-9][0-9][0-9].obj")):
                os.remove(old)
            animated.append((obj, name))
        else:
            spec.kind, spec.obj = "static", os.path.join(out_dir, name + ".obj")
            mesh_files.write_text_atomic(spec.obj, evaluated_obj_text(obj, name, bpy.context.evaluated_depsgraph_get()))
        specs.append(spec)
    if animated:
        # One pass over the frames for all animated colliders; the scene's frame is put back afterwards.
        current = scene.frame_current
        try:
            for frame in range(start, end + 1):
                scene.frame_set(frame)
                depsgraph = bpy.context.evaluated_depsgraph_get()
                for obj, name in animated:
                    mesh_files.write_text_atomic(mesh_files.frame_path(out_dir, name, frame),
                                                 evaluated_obj_text(obj, name, depsgraph))
        finally:
            scene.frame_set(current)
    return specs
