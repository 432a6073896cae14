"""Container shapes behind one protocol, their walls as compiled signed distances, inner baffles, tilt.

A shape is one module registered with :func:`register_shape` (see :mod:`.shape` for what it
answers); :data:`SHAPES` maps ``[container] shape`` to its class. :mod:`.walls` holds the
compiled distance functions every wall force uses; :mod:`.baffles` the inner plates.
"""

from .shape import SHAPES, Shape, ShapeBase, register_shape, shape_from_keys, sizing_keys
# the shapes: one registration (import) line each
from .cuboid import Cuboid
from .cylinder import Cylinder
from .baffles import Baffle
from .tilt import container_vectors, rotation
from .walls import BOX_OUTSIDE, CYLINDER_INSIDE, PLANE, wall_distance, wall_distances

__all__ = ["Cuboid", "Cylinder", "Baffle", "Shape", "ShapeBase", "SHAPES", "register_shape", "shape_from_keys",
           "sizing_keys", "rotation",
           "container_vectors", "wall_distance", "wall_distances", "PLANE", "CYLINDER_INSIDE", "BOX_OUTSIDE"]
