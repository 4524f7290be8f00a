"""Simulate (export, run clothsim in the background, bring the result back), Cancel and Load Result."""
import bpy

from . import export, result, runner

# The one run in progress (one at a time: runs share the cache folder and the machine's cores).
_active = {"job": None, "cancel": False}


def clothsim_binary(context):
    addon = context.preferences.addons.get(__package__)
    path = addon.preferences.binary if addon else "clothsim"
    return bpy.path.abspath(path) if path.startswith("//") else path


def bring_back(operator, context, exported):
    loaded = []
    for c in exported.cloths:
        obj = context.scene.objects.get(c.object_name)
        if obj is None:
            continue
        n = result.load_result(obj, c.save_dir, c.save_name, exported.start_frame, exported.end_frame,
                               exported.work_dir)
        loaded.append(f"{c.object_name}: {n} frames")
    return loaded


def finish(operator, context, job, exported):
    """Turns clothsim's exit into Blender reports; returns the operator's result."""
    code = job.poll()
    if job.cancelled:
        operator.report({"WARNING"}, "clothsim: cancelled; nothing was loaded")
        return {"CANCELLED"}
    if code == runner.EXIT_OK:
        loaded = bring_back(operator, context, exported)
        operator.report({"INFO"}, "clothsim: done; " + ", ".join(loaded))
        return {"FINISHED"}
    if code == runner.EXIT_DIVERGED:
        # Frames written before the divergence are whole: show them, and say why the rest is missing.
        loaded = bring_back(operator, context, exported)
        operator.report({"ERROR"}, "clothsim diverged (exit 3): " + job.error_text() + " Loaded " + ", ".join(loaded))
        return {"CANCELLED"}
    operator.report({"ERROR"}, f"clothsim failed (exit {code}): " + job.error_text())
    return {"CANCELLED"}


class CLOTHSIM_OT_simulate(bpy.types.Operator):
    """Write the scene, run clothsim in the background and play its result on the cloth objects"""
    bl_idname = "clothsim.simulate"
    bl_label = "Simulate"

    _timer = None

    @classmethod
    def poll(cls, context):
        return _active["job"] is None

    def start(self, context):
        try:
            self.exported = export.export_scene(context.scene)
        except (ValueError, OSError) as e:
            self.report({"ERROR"}, f"clothsim: {e}")
            return False
        try:
            self.job = runner.ClothsimJob(clothsim_binary(context), self.exported.path, context.scene.clothsim.threads)
        except RuntimeError as e:
            self.report({"ERROR"}, str(e))
            return False
        return True

    def execute(self, context):
        # Without a window (blender -b) there is no event loop for a modal timer: run to the end here.
        if not self.start(context):
            return {"CANCELLED"}
        self.job.wait()
        return finish(self, context, self.job, self.exported)

    def invoke(self, context, event):
        if bpy.app.background or context.window is None:
            return self.execute(context)
        if not self.start(context):
            return {"CANCELLED"}
        _active.update(job=self.job, cancel=False)
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.2, window=context.window)
        wm.modal_handler_add(self)
        wm.progress_begin(0, 1)
        context.workspace.status_text_set("clothsim: starting…  (Esc cancels)")
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC" or _active["cancel"]:
            self.job.cancel()
        elif event.type != "TIMER":
            return {"PASS_THROUGH"}
        code = self.job.poll()
        if code is None:
            done, total = self.job.progress()
            if total:
                context.window_manager.progress_update(done / total)
                context.workspace.status_text_set(
                    f"clothsim: frame {self.job.last_frame}  {done}/{total}  (Esc cancels)")
            return {"PASS_THROUGH"}
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        context.workspace.status_text_set(None)
        _active.update(job=None, cancel=False)
        out = finish(self, context, self.job, self.exported)
        for area in context.screen.areas if context.screen else ():
            area.tag_redraw()
        return out


class CLOTHSIM_OT_cancel(bpy.types.Operator):
    """Stop the clothsim run in progress"""
    bl_idname = "clothsim.cancel"
    bl_label = "Cancel"

    @classmethod
    def poll(cls, context):
        return _active["job"] is not None

    def execute(self, context):
        _active["cancel"] = True
        return {"FINISHED"}


class CLOTHSIM_OT_load(bpy.types.Operator):
    """Load the frames of the last run from the cache folder onto the cloth objects, without simulating"""
    bl_idname = "clothsim.load"
    bl_label = "Load Result"

    def execute(self, context):
        scene = context.scene
        work_dir = export.work_dir_of(scene)
        start, end = export.frame_range(scene)
        loaded = []
        for obj, name in export.cloth_objects(scene):
            try:
                n = result.load_result(obj, export.frames_dir_of(work_dir), name, start, end, work_dir)
            except ValueError as e:
                self.report({"ERROR"}, f"clothsim: {e}")
                return {"CANCELLED"}
            loaded.append(f"{obj.name}: {n} frames")
        self.report({"INFO"}, "clothsim: " + (", ".join(loaded) or "no cloth object"))
        return {"FINISHED"}


class CLOTHSIM_OT_write_scene(bpy.types.Operator):
    """Write the scene and meshes to the cache folder without running clothsim (to run it elsewhere)"""
    bl_idname = "clothsim.write_scene"
    bl_label = "Write Scene"

    def execute(self, context):
        try:
            exported = export.export_scene(context.scene)
        except (ValueError, OSError) as e:
            self.report({"ERROR"}, f"clothsim: {e}")
            return {"CANCELLED"}
        self.report({"INFO"}, f"clothsim: wrote {exported.path}")
        return {"FINISHED"}


classes = (CLOTHSIM_OT_simulate, CLOTHSIM_OT_cancel, CLOTHSIM_OT_load, CLOTHSIM_OT_write_scene)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    job = _active["job"]
    if job is not None:
        job.cancel()
        _active.update(job=None, cancel=False)
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
