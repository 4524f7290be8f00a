"""Renders the pictures of docs/blender.md headless, with the add-on and the real clothsim binary:

  blender -b --factory-startup --python tools/blender/render_docs.py -- build/clothsim docs/img
  xvfb-run -s "-screen 0 1920x1300x24" blender --factory-startup --python tools/blender/render_docs.py \
      -- build/clothsim docs/img

A 1 m sheet with a colour-grid texture, pinned by a vertex group at two corners, in a light wind; Workbench
renders frames 1, 24 and 48 of the result played back on the object (texture and UVs kept). With a window
(the second command, on a virtual X display) it captures the add-on's panel and the whole window instead."""
import math
import os
import sys

import bpy
import numpy as np

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
run.timestep = 0.0002 if bpy.app.background else 0.00005
run.wind_velocity = (1.0, 2.0, 0.0)
run.wind_strength = 0.25
run.air_damping = 0.05

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


def render_frames():
    for frame in (1, 24, 48):
        scene.frame_set(frame)
        scene.render.filepath = os.path.join(OUT, f"blender_sheet_{frame:04d}.png")
        bpy.ops.render.render(write_still=True)


def show_physics_tab():
    """With a window: run Simulate as the user does (modal, progress in the status bar), then capture."""
    window = bpy.context.window_manager.windows[0]
    for obj in scene.objects:
        obj.select_set(obj == sheet)
    bpy.context.view_layer.objects.active = sheet
    for area in window.screen.areas:
        if area.type == "PROPERTIES":
            area.spaces.active.context = "PHYSICS"
        if area.type == "VIEW_3D":
            space = area.spaces.active
            space.shading.color_type = "TEXTURE"
            space.overlay.show_floor = space.overlay.show_axis_x = space.overlay.show_axis_y = False
            space.region_3d.view_perspective = "CAMERA"
            space.region_3d.view_camera_zoom = 15
            view3d = area
    scene.clothsim.threads = 1  # a slower run, so that the status bar is caught mid-way
    with bpy.context.temp_override(window=window, area=view3d):
        bpy.ops.clothsim.simulate("INVOKE_DEFAULT")
    bpy.app.timers.register(watch_run, first_interval=0.1)


state = {"progress_shot": False}


def watch_run():
    from clothsim_addon import operators
    job = operators._active["job"]
    window = bpy.context.window_manager.windows[0]
    if job is not None:
        done, total = job.progress()
        if not state["progress_shot"] and total and done >= total // 4:
            state["progress_shot"] = True
            capture_status_bar(window)
        return 0.05
    if sheet.modifiers[0].type != "MESH_CACHE":
        print("render_docs: the modal Simulate did not load the result")
        sys.exit(1)
    scene.frame_set(30)
    bpy.app.timers.register(capture, first_interval=1.0)
    return None


def capture_status_bar(window):
    path = os.path.join(OUT, "blender_progress.png")
    with bpy.context.temp_override(window=window):
        bpy.ops.screen.screenshot(filepath=path)
    shot = bpy.data.images.load(path)
    w, h = shot.size
    rows, cols = 26, w // 2  # the status bar: the bottom rows of the window, left half
    pixels = np.array(shot.pixels[:], dtype=np.float32).reshape(h, w, 4)[:rows, :cols]
    bar = bpy.data.images.new("status_bar", cols, rows)
    bar.pixels[:] = pixels.ravel()
    bar.filepath_raw = path
    bar.file_format = "PNG"
    bar.save()


def capture():
    window = bpy.context.window_manager.windows[0]
    props = max((a for a in window.screen.areas if a.type == "PROPERTIES"), key=lambda a: a.height)
    region = next(r for r in props.regions if r.type == "WINDOW")
    with bpy.context.temp_override(window=window, area=props, region=region):
        bpy.ops.screen.screenshot_area(filepath=os.path.join(OUT, "blender_panel.png"))
    with bpy.context.temp_override(window=window):
        bpy.ops.screen.screenshot(filepath=os.path.join(OUT, "blender_window.png"))
    # Half size keeps the committed PNG small; the panel has its own full-size picture.
    shot = bpy.data.images.load(os.path.join(OUT, "blender_window.png"))
    shot.scale(shot.size[0] // 2, shot.size[1] // 2)
    shot.save()
    bpy.ops.wm.quit_blender()


if bpy.app.background:
    assert bpy.ops.clothsim.simulate() == {"FINISHED"}
    render_frames()
else:
    bpy.app.timers.register(show_physics_tab, first_interval=1.0)
