"""Containers and their walls: cuboid, cylinder, tilt; signed distance + normal defined once.

See :mod:`.walls` for the compiled distance functions every wall force uses.
"""

from .cuboid import Cuboid
from .cylinder import Cylinder
from .tilt import container_vectors, rotation
from .walls import CYLINDER_INSIDE, PLANE, wall_distance, wall_distances

__all__ = ["Cuboid", "Cylinder", "rotation", "container_vectors", "wall_distance", "wall_distances",
           "PLANE", "CYLINDER_INSIDE"]
