"""The scene file clothsim reads (io/scene_xml.cpp), written from plain Python values.

No bpy here: the panel's settings are gathered into the dataclasses below by export.py, so this part can be
checked with plain Python against `clothsim validate`. Attribute names and units follow docs/scene-format.md.
"""
from dataclasses import dataclass, field
from typing import Dict, List, Sequence, Tuple
from xml.sax.saxutils import quoteattr

Vec3 = Tuple[float, float, float]


@dataclass
class ClothSpec:
    name: str
    obj: str                      # mesh path, absolute or relative to the scene file
    save_dir: str
    save_name: str
    density: float = 0.2          # kg/m^2
    stiffness: float = 1000.0     # N/m per spring
    bend: float = 1.0             # bend springs: stiffness * bend
    damping: float = 0.1          # N s/m per spring
    thickness: float = 0.005      # m
    friction: float = 0.3
    restitution: float = 0.0
    self_collision: bool = False
    cloth_collision: bool = True  # collides with the scene's other cloths
    max_strain: float = 0.0       # Provot strain limit, (length - rest)/rest; 0: none
    pins: List[int] = field(default_factory=list)  # vertex indices, from 0
    # Parameter maps: element name (density, mass, stiffness, damping, thickness) -> (min, max, grey map path),
    # value = lerp(min, max, grey); a mapped element replaces its value, and a mass map replaces the density.
    maps: Dict[str, Tuple[float, float, str]] = field(default_factory=dict)


@dataclass
class ColliderSpec:
    kind: str                     # "static", "sphere" or "plane"
    name: str
    friction: float = 0.3
    obj: str = ""                 # static: one mesh ...
    sequence: str = ""            # ... or a frame pattern, '#' run = frame number
    center: Vec3 = (0.0, 0.0, 0.0)
    radius: float = 1.0           # m
    point: Vec3 = (0.0, 0.0, 0.0)
    normal: Vec3 = (0.0, 0.0, 1.0)


@dataclass
class SceneSpec:
    timestep: float = 0.001       # s
    fps: float = 24.0
    start_frame: int = 1
    end_frame: int = 48
    integrator: str = "symplectic"
    gravity: Vec3 = (0.0, 0.0, -9.81)   # Blender is Z-up; the add-on writes world space unchanged
    wind_velocity: Vec3 = (0.0, 0.0, 0.0)
    wind_strength: float = 0.0    # kg/(m^2 s)
    air_damping: float = 0.0      # 1/s
    external_acceleration: Vec3 = (0.0, 0.0, 0.0)  # m/s^2, added to gravity
    random_amplitude: float = 0.0  # m/s^2; 0: no random gusts
    random_seed: int = 1
    random_period: float = 0.5    # s between the gust field's nodes in time
    random_cell_size: float = 0.5  # m between them in space
    cloth_collision: bool = True  # different cloths collide with each other
    cloths: List[ClothSpec] = field(default_factory=list)
    colliders: List[ColliderSpec] = field(default_factory=list)


def _collider_attrs(c: ColliderSpec):
    if c.kind == "sphere":
        shape = [("center", _vec(c.center)), ("radius", _num(c.radius))]
    elif c.kind == "plane":
        shape = [("point", _vec(c.point)), ("normal", _vec(c.normal))]
    else:
        shape = [("sequence", c.sequence)] if c.sequence else [("obj", c.obj)]
    return [("name", c.name)] + shape + [("friction", _num(c.friction))]


def _num(x: float) -> str:
    # Blender keeps its properties in float32: 7 significant digits give back what was typed (0.15, not
    # 0.150000006), and float32 holds no more than that anyway.
    return f"{float(x) + 0.0:.7g}"  # + 0.0 turns -0.0 into 0


def _vec(v: Sequence[float]) -> str:
    return " ".join(_num(c) for c in v)


def _bool(b: bool) -> str:
    return "true" if b else "false"


def _param(c: ClothSpec, element: str, value, extra=()) -> str:
    """<element value=…/>, or <element min max map/> when the cloth has a map for it."""
    if element in c.maps:
        lo, hi, path = c.maps[element]
        pairs = [("min", _num(lo)), ("max", _num(hi)), ("map", path)]
    else:
        pairs = [("value", _num(value))]
    return f"    <{element} " + _attrs(pairs + list(extra)) + "/>"


def _attrs(pairs) -> str:
    return " ".join(f"{k}={quoteattr(str(v))}" for k, v in pairs)


def format_scene(scene: SceneSpec) -> str:
    out = ['<?xml version="1.0"?>', "<!-- Written by the clothsim Blender add-on. -->", "<scene>"]
    out.append("  <simulation " + _attrs([
        ("timestep", _num(scene.timestep) if scene.timestep > 0 else "auto"), ("fps", _num(scene.fps)),
        ("startFrame", int(scene.start_frame)), ("endFrame", int(scene.end_frame)),
        ("integrator", scene.integrator), ("gravity", _vec(scene.gravity)),
        ("clothCollision", _bool(scene.cloth_collision))]) + "/>")
    forces = []
    if any(scene.external_acceleration):
        forces.append("    <external " + _attrs([("acceleration", _vec(scene.external_acceleration))]) + "/>")
    if scene.wind_strength > 0:
        forces.append("    <wind " + _attrs([("velocity", _vec(scene.wind_velocity)),
                                            ("strength", _num(scene.wind_strength))]) + "/>")
    if scene.random_amplitude > 0:
        forces.append("    <random " + _attrs([
            ("amplitude", _num(scene.random_amplitude)), ("seed", int(scene.random_seed)),
            ("period", _num(scene.random_period)), ("cellSize", _num(scene.random_cell_size))]) + "/>")
    if scene.air_damping > 0:
        forces.append("    <airDamping " + _attrs([("value", _num(scene.air_damping))]) + "/>")
    if forces:
        out += ["  <forces>"] + forces + ["  </forces>"]
    for c in scene.colliders:
        out.append(f"  <{c.kind} " + _attrs(_collider_attrs(c)) + "/>")
    for c in scene.cloths:
        out.append("  <cloth " + _attrs([
            ("name", c.name), ("obj", c.obj), ("saveDir", c.save_dir), ("saveName", c.save_name),
            ("friction", _num(c.friction)), ("restitution", _num(c.restitution)),
            ("selfCollision", _bool(c.self_collision)), ("clothCollision", _bool(c.cloth_collision))] +
            ([("maxStrain", _num(c.max_strain))] if c.max_strain > 0 else [])) + ">")
        if "mass" in c.maps:
            out.append(_param(c, "mass", None))
        else:
            out.append(_param(c, "density", c.density))
        out.append(_param(c, "stiffness", c.stiffness, [("bend", _num(c.bend))]))
        out.append(_param(c, "damping", c.damping))
        out.append(_param(c, "thickness", c.thickness))
        if c.pins:
            out.append("    <pins " + _attrs([("vertices", " ".join(str(int(i)) for i in c.pins))]) + "/>")
        out.append("  </cloth>")
    out.append("</scene>")
    return "\n".join(out) + "\n"


def write_scene(path: str, scene: SceneSpec) -> None:
    with open(path, "w", encoding="utf-8") as f:
        f.write(format_scene(scene))
