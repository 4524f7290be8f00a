"""Renders the pictures of docs/blender.md headless, with the add-on and the real clothsim binary:

  blender -b --factory-startup --python tools/blender/render_docs.py -- build/clothsim docs/img

A 1 m sheet with a colour-grid texture, pinned by a vertex group at two corners, in a light wind; Workbench
renders frames 1, 24 and 48 of the result played back on the object (texture and UVs kept)."""
import math
import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import addon_utils  # noqa: E402

argv = sys.argv[sys.argv.index("--") + 1:]
BINARY, OUT = os.path.abspath(argv[0]), os.path.abspath(argv[1])
addon_utils.enable("clothsim_addon", default_set=True, handle_error=None)
bpy.context.preferences.addons["clothsim_addon"].preferences.binary = BINARY

scene = bpy.context.scene
for obj in list(scene.objects):
    bpy.data.objects.remove(obj)

# The sheet: a 24 x 24 grid standing in the XZ plane, its top edge at z = 1.6.
bpy.ops.mesh.primitive_grid_add(x_subdivisions=23, y_subdivisions=23, size=1.0, location=(0, 0, 1.1),
                                rotation=(math.radians(90), 0, 0))
sheet = bpy.context.object
sheet.name = "Sheet"
top = max(v.co.y for v in sheet.data.vertices)
xs = [v.co.x for v in sheet.data.vertices]
pins = [v.index for v in sheet.data.vertices if v.co.y == top and v.co.x in (min(xs), max(xs))]
sheet.vertex_groups.new(name="pins").add(pins, 1.0, "REPLACE")
image = bpy.data.images.new("grid", 512, 512)
image.generated_type = "COLOR_GRID"
material = bpy.data.materials.new("Grid")
material.use_nodes = True
tex = material.node_tree.nodes.new("ShaderNodeTexImage")
tex.image = image
material.node_tree.links.new(tex.outputs["Color"], material.node_tree.nodes["Principled BSDF"].inputs["Base Color"])
sheet.data.materials.append(material)
bpy.ops.object.shade_smooth()
s = sheet.clothsim
s.role = "CLOTH"
s.density, s.stiffness, s.bend, s.damping, s.thickness = 0.15, 60.0, 0.05, 0.01, 0.003
s.pin_group = "pins"

bpy.ops.mesh.primitive_plane_add(size=4, location=(0, 0, 0))

scene.frame_start, scene.frame_end = 1, 48
run = scene.clothsim
run.timestep = 0.0002
run.wind_velocity = (1.0, 2.0, 0.0)
run.wind_strength = 0.25
run.air_damping = 0.05
run.cache_dir = os.path.join(OUT, "..", "..", "build", "blender_docs_cache")
assert bpy.ops.clothsim.simulate() == {"FINISHED"}

bpy.ops.object.camera_add(location=(2.2, -3.0, 1.6))
camera = bpy.context.object
target = bpy.data.objects.new("target", None)
target.location = (0, 0, 0.9)
scene.collection.objects.link(target)
track = camera.constraints.new("TRACK_TO")
track.target = target
scene.camera = camera
scene.render.engine = "BLENDER_WORKBENCH"
scene.display.shading.color_type = "TEXTURE"
scene.display.shading.light = "STUDIO"
scene.render.resolution_x, scene.render.resolution_y, scene.render.resolution_percentage = 320, 240, 100
scene.render.image_settings.color_mode = "RGB"
scene.render.image_settings.compression = 100
for frame in (1, 24, 48):
    scene.frame_set(frame)
    scene.render.filepath = os.path.join(OUT, f"blender_sheet_{frame:04d}.png")
    bpy.ops.render.render(write_still=True)
