"""Contact laws, one file per literature model, and the registry of damping laws.

- :mod:`.hertz` -- Hertz elasticity shared by the normal laws: stiffness ``4/3 E* sqrt(R*)`` and
  elastic energy ``2/5 k delta^(5/2)``.
- :mod:`.hertz_gonthier` -- normal force, Hertz with Gonthier et al. (2004) damping, eq. (1);
  damping choices ``"calibrated"`` (default) and ``"gonthier"``.
- :mod:`.hertz_tsuji` -- normal force, Hertz with Tsuji et al. (1992) viscoelastic damping as
  LIGGGHTS' ``model hertz`` uses it; damping choice ``"tsuji"``.
- :mod:`.friction_tanh` -- regularised Coulomb friction, eq. (2) (tangential choice ``"tanh"``, default).
- :mod:`.tangential_spring` -- incremental tangential spring, Mindlin's stiffness, Coulomb cap
  (tangential choice ``"spring"``).
- :mod:`.cor_constant`, :mod:`.cor_table`, :mod:`.cor_thornton` -- coefficient of restitution laws,
  one module each behind the protocol of :mod:`.restitution` (registered in :data:`RESTITUTION_LAWS`).

A COR law answers ``restitution(speed)``, ``kernel_table()`` and ``config_value()``
(:class:`.restitution.RestitutionLaw`); the kernels see every law as a table of the damping law's
coefficient over log-spaced impact speeds (:func:`.restitution.tabulate_law`), so one compiled
kernel serves all COR laws. **A new COR law** is one file here and one import line below (its
``@register_restitution`` registers it); nothing else names it. A law of your own (any object with
``restitution(speed)``) runs and is written to config files as the table law of its values
(:func:`kernel_law`). A damping law is a :class:`.damping.DampingLaw`, chosen
by name (``ContactModel.damping``) from :data:`DAMPING_LAWS`; each is compiled into its own
kernels. **A new damping law** is one file here plus one line in :data:`DAMPING_LAWS` (see
:mod:`.damping`). A tangential law is a :class:`.tangential.TangentialLaw`, chosen by name
(``ContactModel.tangential``) from :data:`TANGENTIAL_LAWS` and compiled the same way.
"""

import difflib

from . import friction_tanh, hertz_gonthier, hertz_tsuji, tangential_spring
from .cor_constant import ConstantRestitution, read_coefficient
from .cor_table import TabulatedRestitution
from .cor_thornton import ThorntonRestitution
from .restitution import RESTITUTION_LAWS as _RESTITUTION_LAWS
from .restitution import SPEED_GRID, RestitutionLaw, register_restitution, tabulate_law
from .damping import DampingLaw
from .tangential import TangentialLaw
from .friction_tanh import DEFAULT_TAU
from .hertz import hertz_energy, hertz_stiffness
from .hertz_gonthier import contact_time, damping_parameter
from ..errors import InputError, shown

#: Damping law name -> :class:`~.damping.DampingLaw`: the registry of ``contact.damping``.
DAMPING_LAWS = {law.name: law for law in (*hertz_gonthier.LAWS, *hertz_tsuji.LAWS)}

#: The allowed values of ``contact.damping``, the default first.
DAMPING_CHOICES = tuple(DAMPING_LAWS)

#: Tangential law name -> :class:`~.tangential.TangentialLaw`: the registry of ``contact.tangential``.
TANGENTIAL_LAWS = {law.name: law for law in (friction_tanh.LAW, tangential_spring.LAW)}

#: The allowed values of ``contact.tangential``, the default first.
TANGENTIAL_CHOICES = tuple(TANGENTIAL_LAWS)

#: COR law tag -> class: the registry of ``restitution = {law = ...}`` (:mod:`.restitution`; the
#: imports of the law modules above register them).
RESTITUTION_LAWS = _RESTITUTION_LAWS



def _choices(words) -> str:
    words = [repr(w) for w in words]
    return ", ".join(words[:-1]) + f" or {words[-1]}" if len(words) > 1 else words[0]


def read_restitution(value, section: str, key: str = "restitution"):
    """A COR law as a config gives it: a number (constant) or a table ``{law = <a registered law>,
    ...}``; a law object (anything with ``restitution``) as it is."""
    if hasattr(value, "restitution"):
        return value
    name = f"[{section}] {key}"
    try:
        return _law(value, section, key)
    except InputError as exc:
        msg = str(exc)
        if msg.startswith("["):
            raise
        if msg.startswith("restitution = ") and ": " in msg:
            raise InputError(f"{name} = {shown(value)}: {msg.split(': ', 1)[1]}") from None
        raise InputError(f"[{section}] {msg}") from None


def _law(value, section, key):
    name = f"[{section}] {key}"
    if isinstance(value, (bool, int, float, str)):
        return ConstantRestitution(value=read_coefficient(value, name))
    if not isinstance(value, dict):
        raise InputError(f"{name} = {shown(value)}: give a number such as 0.9 or a table "
                         "{law = 'table', speeds = [...], values = [...]} or {law = 'thornton', "
                         "yield_pressure = '1.5GPa'}")
    law = value.get("law")
    if law is None:
        raise InputError(f"{name}: the table needs law = {_choices(RESTITUTION_LAWS)}")
    cls = RESTITUTION_LAWS.get(law) if isinstance(law, str) else None
    if cls is None:
        near = difflib.get_close_matches(str(law), list(RESTITUTION_LAWS), n=1, cutoff=0.5)
        hint = f"did you mean {near[0]!r}? " if near else ""
        raise InputError(f"{name}: law = {shown(law)} is unknown; {hint}choose {_choices(RESTITUTION_LAWS)}")
    return cls.from_config(value, section, key)


def kernel_law(law) -> RestitutionLaw:
    """``law`` as the COR-law protocol has it (:mod:`.restitution`): a pdamper law as it is; any other
    object with ``restitution(speed)`` as the table law of its values at the kernels' speeds
    (:meth:`TabulatedRestitution.from_law`: the kernels' table of it, bit for bit); one that cannot be
    tabulated so is refused in one line saying how to tabulate it."""
    if isinstance(law, RestitutionLaw):
        return law
    return TabulatedRestitution.from_law(law)


def restitution_value(law):
    """What a config file holds for the COR law ``law``: a number (a constant) or its table; a law of
    your own as the table law of its values (:func:`kernel_law`)."""
    return kernel_law(law).config_value()


__all__ = [
    "ConstantRestitution",
    "TabulatedRestitution",
    "ThorntonRestitution",
    "DampingLaw",
    "DAMPING_LAWS",
    "DAMPING_CHOICES",
    "TangentialLaw",
    "TANGENTIAL_LAWS",
    "TANGENTIAL_CHOICES",
    "read_restitution",
    "RestitutionLaw",
    "RESTITUTION_LAWS",
    "register_restitution",
    "kernel_law",
    "restitution_value",
    "SPEED_GRID",
    "tabulate_law",
    "contact_time",
    "hertz_stiffness",
    "hertz_energy",
    "damping_parameter",
    "DEFAULT_TAU",
]
