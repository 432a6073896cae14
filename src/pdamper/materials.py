"""Materials of particles and container walls (paper Table 1) and their pairwise mixing.

All values SI: Young's modulus [Pa], Poisson ratio [-], density [kg/m^3].
"""

from __future__ import annotations

import difflib
from dataclasses import dataclass

from .errors import InputError, shown
from .schema import check_keys, config_keys, convert_fields, param, read_fields

__all__ = ["Material", "STEEL_S235", "PVC", "TUNGSTEN", "SILICONE", "TPU", "POLYURETHANE", "NBR", "effective_modulus",
           "effective_shear_modulus", "LIBRARY", "read_material"]


@dataclass(frozen=True, kw_only=True)
class Material:
    """An isotropic elastic material.

    Parameters
    ----------
    name : str
        Label used in configs and results.
    youngs_modulus : float
        E [Pa], > 0.
    poisson_ratio : float
        nu [-], in (-1, 0.5).
    density : float
        rho [kg/m^3], > 0.
    restitution : float or None
        The coefficient of restitution of a sphere striking this material, in (0, 1], when it
        is a wall coating whose own restitution is known (None: the contact model's law). A
        ``[[contact.pair]]`` restitution for the pair wins over it.
    """

    name: str = param(kind="text")
    youngs_modulus: float = param(dimension="pressure", paper="steel 208 GPa")
    poisson_ratio: float = param(kind="number", paper="steel 0.3")
    density: float = param(dimension="density", paper="steel 7900 kg/m^3")
    restitution: float | None = param(None, dimension="dimensionless")

    def __post_init__(self):
        convert_fields(self, "material")
        if not (self.youngs_modulus > 0):
            raise InputError(f"material {shown(self.name)}: youngs_modulus = {shown(self.youngs_modulus)} Pa; must be > 0 (steel: 208e9)")
        if not (-1.0 < self.poisson_ratio < 0.5):
            raise InputError(f"material {shown(self.name)}: poisson_ratio = {shown(self.poisson_ratio)}; must be in (-1, 0.5) (steel: 0.3)")
        r = self.restitution
        if r is not None and (isinstance(r, bool) or not isinstance(r, (int, float)) or not 0 < r <= 1):
            raise InputError(f"material {shown(self.name)}: restitution = {shown(r)}; must be in (0, 1] (or omit it)")
        if not (self.density > 0):
            raise InputError(f"material {shown(self.name)}: density = {shown(self.density)} kg/m^3; must be > 0 (steel: 7900)")

    @property
    def reduced_modulus(self) -> float:
        """E / (1 - nu^2) [Pa]: this material's share of 1/E* is its inverse."""
        return self.youngs_modulus / (1.0 - self.poisson_ratio**2)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) [Pa]."""
        return self.youngs_modulus / (2.0 * (1.0 + self.poisson_ratio))


def effective_modulus(a: Material, b: Material) -> float:
    """Hertz effective modulus E* [Pa]: ``1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2``."""
    return 1.0 / (1.0 / a.reduced_modulus + 1.0 / b.reduced_modulus)


def effective_shear_modulus(a: Material, b: Material) -> float:
    """Mindlin's effective shear modulus G* [Pa]: ``1/G* = (2-nu1)/G1 + (2-nu2)/G2`` (the
    tangential stiffness of a Hertz contact is ``8 G* sqrt(R* delta)``,
    :mod:`pdamper.contact.tangential_spring`)."""
    return 1.0 / ((2.0 - a.poisson_ratio) / a.shear_modulus + (2.0 - b.poisson_ratio) / b.shear_modulus)


#: Paper Table 1: sphere steel S235.
STEEL_S235 = Material(name="steel", youngs_modulus=208e9, poisson_ratio=0.3, density=7900.0)
#: Paper Table 1: container PVC.
PVC = Material(name="pvc", youngs_modulus=3e9, poisson_ratio=0.38, density=1400.0)
#: Paper Sect. 6.1 sensitivity value (tungsten): E = 405 GPa, rho = 19250 kg/m^3.
TUNGSTEN = Material(name="tungsten", youngs_modulus=405e9, poisson_ratio=0.28, density=19250.0)

# Wall coatings (Meyer & Seifried 2023 line their container walls with soft polymers). Typical
# values of the material classes, not of one product: measure your coating where it matters.
#: Silicone elastomer (about Shore 50A): E 5-20 MPa, nu 0.47-0.49, rho 1100-1300 kg/m^3
#: (Ashby, Materials Selection in Mechanical Design, 4th ed. 2011, data sheet "Silicone elastomers").
SILICONE = Material(name="silicone", youngs_modulus=10e6, poisson_ratio=0.48, density=1150.0)
#: Thermoplastic polyurethane for 3D printing (Shore 95A): tensile modulus 26 MPa, density
#: 1220 kg/m^3 (Ultimaker TPU 95A technical data sheet); nu 0.45 (nearly incompressible elastomer).
TPU = Material(name="tpu", youngs_modulus=26e6, poisson_ratio=0.45, density=1220.0)
#: Cast polyurethane elastomer (about Shore 90A): E 25-75 MPa, nu 0.45-0.49, rho 1150-1250 kg/m^3
#: (Ashby 2011, data sheet "Polyurethane elastomers (elPU)").
POLYURETHANE = Material(name="polyurethane", youngs_modulus=50e6, poisson_ratio=0.47, density=1200.0)
#: Nitrile rubber (NBR, about Shore 70A): E 4-10 MPa, nu 0.49, rho 1000-1200 kg/m^3 (Ashby 2011,
#: data sheet "Butyl/nitrile rubbers").
NBR = Material(name="nbr", youngs_modulus=7e6, poisson_ratio=0.49, density=1100.0)

#: Named materials a config may refer to by name.
LIBRARY = {m.name: m for m in (STEEL_S235, PVC, TUNGSTEN, SILICONE, TPU, POLYURETHANE, NBR)}


def read_material(value, section: str) -> Material:
    """A material as a config gives it: a name of :data:`LIBRARY` (``"steel"``) or an inline table
    ``{name, youngs_modulus, poisson_ratio, density}`` (named after ``section`` when it has no
    name: ``"particles #2"`` -> ``"particles-2"``); a :class:`Material` as it is."""
    if isinstance(value, Material):
        return value
    name = f"[{section}] material"
    if isinstance(value, str):
        key = value.strip().lower()
        if key in LIBRARY:
            return LIBRARY[key]
        near = difflib.get_close_matches(key, list(LIBRARY), n=1, cutoff=0.5)
        hint = f"did you mean {near[0]!r}? " if near else ""
        raise InputError(f"{name} = {shown(value)} is not a known material; {hint}known: "
                         + ", ".join(map(repr, LIBRARY)) + " (or give an inline table {name = ..., "
                         "youngs_modulus = ..., poisson_ratio = ..., density = ...})")
    if not isinstance(value, dict):
        raise InputError(f"{name} = {shown(value)}: give a material name such as 'steel' or an inline table "
                         "{youngs_modulus = '208GPa', poisson_ratio = 0.3, density = '7900kg/m^3'}")
    sub = f"{section}.material"
    keys = config_keys(Material)
    check_keys(value, sub, keys)
    for req in ("youngs_modulus", "poisson_ratio", "density"):
        if req not in value:
            raise InputError(f"[{sub}] {req} is missing; an inline material needs youngs_modulus, "
                             "poisson_ratio and density")
    mname = value.get("name", section.replace(" #", "-"))
    if not isinstance(mname, str) or not mname:
        raise InputError(f"[{sub}] name = {shown(mname)} must be a non-empty string")
    return Material(**{**read_fields(value, sub, Material), "name": mname})
