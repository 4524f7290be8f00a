"""Blender meshes as clothsim's OBJ input: world space, triangulated by Blender's own loop triangles."""
import numpy as np

from . import mesh_files


def world_positions(mesh, matrix_world):
    co = np.empty(3 * len(mesh.vertices), dtype=np.float64)
    mesh.vertices.foreach_get("co", co)
    m = np.array(matrix_world, dtype=np.float64)
    return co.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3]


def loose_edges(mesh):
    """Edges in no face: Blender's sewing edges (its cloth's "Sewing" springs pull their ends together)."""
    return [tuple(e.vertices) for e in mesh.edges if e.is_loose]


def mesh_obj_text(mesh, matrix_world, name, with_uvs=True, with_stitches=False):
    """A mesh in world space as triangles (faces split by Blender's own loop triangulation); with_stitches, its
    loose edges as stitch records."""
    mesh.calc_loop_triangles()
    nt = len(mesh.loop_triangles)
    tri_v = np.empty(3 * nt, dtype=np.int64)
    mesh.loop_triangles.foreach_get("vertices", tri_v)
    uvs = tri_uv = None
    if with_uvs and mesh.uv_layers.active is not None:
        uv = np.empty(2 * len(mesh.loops), dtype=np.float64)
        mesh.uv_layers.active.data.foreach_get("uv", uv)
        tri_uv = np.empty(3 * nt, dtype=np.int64)
        mesh.loop_triangles.foreach_get("loops", tri_uv)
        uvs, tri_uv = uv.reshape(-1, 2), tri_uv.reshape(-1, 3)
    stitches = loose_edges(mesh) if with_stitches else ()
    return mesh_files.format_obj(name, world_positions(mesh, matrix_world), tri_v.reshape(-1, 3), tri_uv, uvs,
                                 stitches)
