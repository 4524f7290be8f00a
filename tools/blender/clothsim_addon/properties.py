"""Settings stored in the .blend file: per object (role and material of the cloth) and per scene (the run).
Defaults are clothsim's own (core/scene_desc.h), so an untouched panel writes the scene clothsim would assume."""
import bpy
from bpy.props import (BoolProperty, EnumProperty, FloatProperty, FloatVectorProperty, IntProperty,
                       PointerProperty, StringProperty)


class ClothsimPreferences(bpy.types.AddonPreferences):
    bl_idname = __package__

    binary: StringProperty(
        name="clothsim binary", subtype="FILE_PATH", default="clothsim",
        description="Path of the clothsim executable (build/clothsim in a source tree); a bare name is looked "
                    "up on PATH")

    def draw(self, context):
        self.layout.prop(self, "binary")


class ClothsimObjectSettings(bpy.types.PropertyGroup):
    role: EnumProperty(
        name="Role", default="NONE",
        items=[("NONE", "None", "Not part of the clothsim scene"),
               ("CLOTH", "Cloth", "Simulated by clothsim: exported as a <cloth> element"),
               ("COLLIDER", "Collider", "An obstacle the cloth collides with")])
    collider_shape: EnumProperty(
        name="Shape", default="MESH",
        items=[("MESH", "Mesh", "The evaluated mesh, triangulated (<static obj>)"),
               ("SPHERE", "Sphere", "An exact sphere: the origin and half the largest dimension (<sphere>)"),
               ("PLANE", "Plane", "An infinite plane through the origin, normal along local +Z (<plane>)")])
    collider_animated: BoolProperty(
        name="Animated", default=False,
        description="Export one OBJ per frame from the evaluated (moved, deformed) mesh (<static sequence>)")
    density: FloatProperty(name="Density", default=0.2, min=1e-6, soft_max=5.0, precision=4,
                           description="Areal density, kg/m^2 (<density value>)")
    stiffness: FloatProperty(name="Stiffness", default=1000.0, min=0.0, soft_max=1e5,
                             description="Spring stiffness, N/m per spring (<stiffness value>)")
    bend: FloatProperty(name="Bend factor", default=1.0, min=0.0, soft_max=2.0,
                        description="Bend spring stiffness as a factor of Stiffness (<stiffness bend>)")
    damping: FloatProperty(name="Damping", default=0.1, min=0.0, soft_max=10.0, precision=4,
                           description="Spring damping, N s/m per spring (<damping value>)")
    thickness: FloatProperty(name="Thickness", default=0.005, min=1e-6, soft_max=0.1, precision=4,
                             subtype="DISTANCE", unit="LENGTH",
                             description="Collision thickness, m (<thickness value>)")
    friction: FloatProperty(name="Friction", default=0.3, min=0.0, soft_max=2.0,
                            description="Coulomb friction coefficient (<cloth friction>, <static|sphere|plane friction>)")
    restitution: FloatProperty(name="Restitution", default=0.0, min=0.0, soft_max=1.0,
                               description="Bounce, 0..1 (<cloth restitution>); clothsim rejects values over 1")
    self_collision: BoolProperty(name="Self-collision", default=False,
                                 description="Collide the cloth with itself (<cloth selfCollision>)")
    pin_group: StringProperty(name="Pin group",
                              description="Vertex group of pinned vertices (<pins vertices>); empty: no pins")
    pin_weight: FloatProperty(name="Pin weight", default=0.5, min=0.0, max=1.0,
                              description="Vertices whose weight in the pin group is at least this are pinned")


class ClothsimSceneSettings(bpy.types.PropertyGroup):
    integrator: EnumProperty(
        name="Integrator", default="symplectic",
        items=[("symplectic", "Symplectic Euler", "Semi-implicit Euler"),
               ("euler", "Explicit Euler", "Forward Euler"),
               ("rk4", "Runge-Kutta 4", "Classic fourth-order Runge-Kutta")],
        description="<simulation integrator>")
    timestep: FloatProperty(name="Time step", default=0.0, min=0.0, soft_max=0.01, precision=6,
                            description="Requested time step, s (<simulation timestep>), 0 for automatic "
                                        "(timestep=\"auto\"); clothsim shortens it to divide a frame evenly")
    use_scene_range: BoolProperty(name="Scene frame range", default=True,
                                  description="Simulate the scene's frame range")
    frame_start: IntProperty(name="Start", default=1, min=0, description="<simulation startFrame>")
    frame_end: IntProperty(name="End", default=48, min=0, description="<simulation endFrame>")
    use_scene_gravity: BoolProperty(name="Scene gravity", default=True,
                                    description="Use the scene's gravity (Scene properties > Gravity)")
    gravity: FloatVectorProperty(name="Gravity", default=(0.0, 0.0, -9.81), subtype="ACCELERATION",
                                 description="m/s^2, world space (<simulation gravity>)")
    wind_velocity: FloatVectorProperty(name="Wind velocity", default=(0.0, 0.0, 0.0), subtype="VELOCITY",
                                       description="m/s, world space (<wind velocity>)")
    wind_strength: FloatProperty(name="Wind strength", default=0.0, min=0.0, soft_max=10.0,
                                 description="kg/(m^2 s); 0: no wind (<wind strength>)")
    air_damping: FloatProperty(name="Air damping", default=0.0, min=0.0, soft_max=5.0,
                               description="1/s (<airDamping value>)")
    cache_dir: StringProperty(name="Cache folder", subtype="DIR_PATH", default="//clothsim_cache",
                              description="Where the scene, meshes and frames are written ('//' is the .blend "
                                          "file's folder; a temporary folder while the file is unsaved)")
    threads: IntProperty(name="Threads", default=0, min=0, description="clothsim --threads; 0: all cores")


classes = (ClothsimPreferences, ClothsimObjectSettings, ClothsimSceneSettings)


def register():
    for c in classes:
        bpy.utils.register_class(c)
    bpy.types.Object.clothsim = PointerProperty(type=ClothsimObjectSettings)
    bpy.types.Scene.clothsim = PointerProperty(type=ClothsimSceneSettings)


def unregister():
    del bpy.types.Scene.clothsim
    del bpy.types.Object.clothsim
    for c in reversed(classes):
        bpy.utils.unregister_class(c)
