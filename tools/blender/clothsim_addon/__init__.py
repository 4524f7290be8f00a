"""clothsim for Blender: mark meshes as cloth, run the clothsim simulator in the background and play its
result on the objects. See docs/blender.md."""

bl_info = {
    "name": "clothsim",
    "author": "clothsim developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Properties > Physics > clothsim",
    "description": "Set up, run and bring back a clothsim cloth simulation",
    "category": "Physics",
}

try:
    import numpy  # noqa: F401 (Blender's own builds bundle it; Debian's blender needs python3-numpy)
except ImportError as e:
    raise ImportError("the clothsim add-on needs numpy to read and write large frame sequences quickly; on "
                      "Debian: apt-get install python3-numpy") from e

from . import operators, panels, properties  # noqa: E402

_modules = (properties, operators, panels)


def register():
    for m in _modules:
        m.register()


def unregister():
    for m in reversed(_modules):
        m.unregister()
