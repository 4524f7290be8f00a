"""Properties editor > Physics: the object's role and material, and the run settings of the scene."""
import bpy

from . import operators


def props(layout, data, *names):
    for name in names:
        layout.prop(data, name)


class PhysicsTabPanel:
    """Where both panels live: Properties editor > Physics, for mesh objects."""
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "physics"

    @classmethod
    def poll(cls, context):
        return context.object is not None and context.object.type == "MESH"


class CLOTHSIM_PT_object(PhysicsTabPanel, bpy.types.Panel):
    bl_label = "clothsim"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        obj = context.object
        s = obj.clothsim
        layout.prop(s, "role")
        if s.role == "NONE":
            return
        col = layout.column()
        if s.role == "CLOTH":
            props(col, s, "density", "stiffness", "bend", "damping", "thickness")
        if s.role == "CLOTH":
            props(col, s, "friction", "restitution", "self_collision", "cloth_collision", "max_strain")
            col.prop_search(s, "pin_group", obj, "vertex_groups")
            sub = col.column()
            sub.active = bool(s.pin_group)
            sub.prop(s, "pin_weight")
            for group, fields in (("stiffness_group", ("stiffness_max",)), ("thickness_group", ("thickness_max",)),
                                  ("mass_group", ("mass_min", "mass_max"))):
                col.prop_search(s, group, obj, "vertex_groups")
                sub = col.column()
                sub.active = bool(getattr(s, group))
                props(sub, s, *fields)
        else:
            props(col, s, "collider_shape", "friction")
            if s.collider_shape == "MESH":
                col.prop(s, "collider_animated")


class CLOTHSIM_PT_run(PhysicsTabPanel, bpy.types.Panel):
    bl_label = "clothsim run"

    def draw(self, context):
        layout = self.layout
        layout.use_property_split = True
        s = context.scene.clothsim
        col = layout.column()
        props(col, s, "integrator", "timestep", "use_scene_range")
        if not s.use_scene_range:
            props(col, s, "frame_start", "frame_end")
        col.prop(s, "use_scene_gravity")
        if not s.use_scene_gravity:
            col.prop(s, "gravity")
        props(col, s, "wind_velocity", "wind_strength", "air_damping", "external_acceleration", "random_amplitude")
        sub = col.column()
        sub.active = s.random_amplitude > 0
        props(sub, s, "random_seed", "random_period", "random_cell_size")
        props(col, s, "cloth_collision", "cache_dir", "threads")
        row = layout.row(align=True)
        if operators._active["job"] is None:
            row.operator("clothsim.simulate", icon="PLAY")
        else:
            row.operator("clothsim.cancel", icon="CANCEL")
        row.operator("clothsim.load", icon="FILE_REFRESH")
        row.operator("clothsim.write_scene", icon="EXPORT")


classes = (CLOTHSIM_PT_object, CLOTHSIM_PT_run)


def register():
    for c in classes:
        bpy.utils.register_class(c)


def unregister():
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
