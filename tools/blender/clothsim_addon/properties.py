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
    cloth_collision: BoolProperty(name="Cloth collision", default=True,
                                  description="Collide with the scene's other cloths (<cloth clothCollision>)")
    max_strain: FloatProperty(name="Max strain", default=0.0, min=0.0, soft_max=0.5, precision=3,
                              description="Provot strain limit, largest (length - rest)/rest of a spring; 0: none "
                                          "(<cloth maxStrain>)")
    # Vertex groups baked into grey-scale maps (tools/blender/clothsim_addon/map_bake.py): the field above is the
    # value at weight 0, the "at weight 1" field the value at weight 1, linear between.
    stiffness_group: StringProperty(name="Stiffness group",
                                    description="Vertex group scaling the stiffness (<stiffness min max map>); "
                                                "empty: uniform Stiffness")
    stiffness_max: FloatProperty(name="Stiffness at weight 1", default=1000.0, min=0.0, soft_max=1e5,
                                 description="Stiffness, N/m, of a vertex of weight 1 in the stiffness group")
    thickness_group: StringProperty(name="Thickness group",
                                    description="Vertex group scaling the thickness (<thickness min max map>)")
    thickness_max: FloatProperty(name="Thickness at weight 1", default=0.005, min=1e-6, soft_max=0.1,
                                 precision=4, subtype="DISTANCE", unit="LENGTH",
                                 description="Thickness, m, of a vertex of weight 1 in the thickness group")
    mass_group: StringProperty(name="Mass group",
                               description="Vertex group giving per-vertex masses (<mass min max map>) instead of "
                                           "Density; empty: Density")
    mass_min: FloatProperty(name="Mass at weight 0", default=0.001, min=1e-9, soft_max=1.0, precision=5,
                            description="Mass, kg, of a vertex of weight 0 (or outside) the mass group")
    mass_max: FloatProperty(name="Mass at weight 1", default=0.001, min=1e-9, soft_max=1.0, precision=5,
                            description="Mass, kg, of a vertex of weight 1 in the mass group")
    pin_group: StringProperty(name="Pin group",
                              description="Vertex group of pinned vertices (<pins vertices>); empty: no pins")
    pin_weight: FloatProperty(name="Pin weight", default=0.5, min=0.0, max=1.0,
                              description="Vertices whose weight in the pin group is at least this are pinned")


class ClothsimSceneSettings(bpy.types.PropertyGroup):
    integrator: EnumProperty(
        name="Integrator", default="symplectic",
        items=[("symplectic", "Symplectic Euler", "Semi-implicit Euler"),
               ("euler", "Explicit Euler", "Forward Euler"),
               ("rk4", "Runge-Kutta 4", "Classic fourth-order Runge-Kutta"),
               ("implicit", "Implicit (backward Euler)", "Baraff-Witkin backward Euler: stable at large steps")],
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
    external_acceleration: FloatVectorProperty(name="External acceleration", default=(0.0, 0.0, 0.0),
                                               subtype="ACCELERATION",
                                               description="m/s^2 added to gravity, world space (<external>)")
    random_amplitude: FloatProperty(name="Gust amplitude", default=0.0, min=0.0, soft_max=20.0,
                                    description="Largest random acceleration per axis, m/s^2; 0: none (<random>)")
    random_seed: IntProperty(name="Gust seed", default=1, min=0, description="<random seed>")
    random_period: FloatProperty(name="Gust period", default=0.5, min=1e-3, soft_max=5.0,
                                 description="s between the gust field's nodes in time (<random period>)")
    random_cell_size: FloatProperty(name="Gust cell size", default=0.5, min=1e-3, soft_max=10.0,
                                    subtype="DISTANCE", unit="LENGTH",
                                    description="m between the gust field's nodes in space (<random cellSize>)")
    cloth_collision: BoolProperty(name="Cloths collide", default=True,
                                  description="Different cloths collide with each other (<simulation "
                                              "clothCollision>)")
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
