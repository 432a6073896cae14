"""A structure of N modes the container rides on, two-way coupled (``[structure]`` with ``modes =
[...]`` given as data, or ``matrices = ...`` from FE matrices, :mod:`.matrices`)."""

from __future__ import annotations

import copy
import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, resolved, shown
from ..excitation import register_drive
from ..schema import param
from .base import StructureBase
from .matrices import modes_from_matrices

__all__ = ["ModalStructure", "MODE_KEYS", "MODE_LIMIT_HZ"]

#: Keys of one entry of ``[structure] modes``: (unit dimension, example).
MODE_KEYS = {"frequency": ("frequency", "'2Hz'"), "damping_ratio": ("dimensionless", "0.005"),
             "modal_mass": ("mass", "'7kg'"), "damper": ("dimensionless", "1.0"),
             "force": ("dimensionless", "1.0"), "response": ("dimensionless", "1.0")}
_MODE_KEYS = MODE_KEYS
#: The highest mode a modal structure may carry [Hz]: omega h = 0.31 at a 50 us step (the
#: velocity-Verlet step of each mode is stable for omega h < 2); modes this high do not take part
#: in a damper's few-Hz motion.
MODE_LIMIT_HZ = 1000.0
_GEAR_STEP_BOUND = 50e-6
#: The keys that belong to matrices = ... (not to modes = [...]).
_FE_KEYS = ("damper_dof", "force_dof", "response_dof", "rayleigh", "modes_kept", "rayleigh_modes", "rayleigh_ratios")


def _read_mode(entry, k: int) -> dict:
    """One ``modes`` entry as SI floats (``frequency`` [Hz], ``modal_mass`` [kg], the rest plain)."""
    from ..units import to_si

    label = f"structure.modes[{k}]"
    if not isinstance(entry, dict):
        raise InputError(f"{label} = {shown(entry)}; give a table {{frequency = '2Hz', damping_ratio = 0.005, "
                         "modal_mass = '7kg', damper = 1.0, force = 1.0, response = 1.0}")
    unknown = [key for key in entry if key not in _MODE_KEYS]
    if unknown:
        raise InputError(f"{label}: unknown key {shown(unknown[0])}; a mode has {', '.join(_MODE_KEYS)}")
    out = {}
    for key, (dim, ex) in _MODE_KEYS.items():
        if key not in entry:
            if key in ("force", "response"):
                out[key] = out.get("damper", 1.0)
                continue
            raise InputError(f"{label}.{key} is missing, e.g. {key} = {ex}")
        v = entry[key]
        if isinstance(v, bool):
            raise InputError(f"{label}.{key} = {shown(v)}; must be a number, e.g. {ex}")
        v = to_si(v, dim, name=f"{label}.{key}") if isinstance(v, str) or hasattr(v, "magnitude") else v
        if not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InputError(f"{label}.{key} = {shown(entry[key])}; must be a finite number, e.g. {ex}")
        out[key] = float(v)
    if not out["frequency"] > 0:
        raise InputError(f"{label}.frequency = {shown(entry['frequency'])}; must be > 0, e.g. '2Hz'")
    if not out["modal_mass"] > 0:
        raise InputError(f"{label}.modal_mass = {shown(entry['modal_mass'])}; must be > 0, e.g. '7kg'")
    if not 0.0 <= out["damping_ratio"] < 1.0:
        raise InputError(f"{label}.damping_ratio = {shown(entry['damping_ratio'])}; must be in [0, 1), e.g. 0.005")
    if out["damper"] == 0.0:
        raise InputError(f"{label}.damper = 0: the mode shape is zero at the damper, so the damper cannot act "
                         "on this mode; leave the mode out or give its value at the damper (e.g. damper = 1.0)")
    return out


@dataclass(frozen=True, kw_only=True)
class _Modes:
    """The modal structure's own fields (first in the written config: see :mod:`.base`; the
    Rayleigh pair last, written only when given)."""

    modes: tuple = param((), kind="custom")
    matrices: object = param(None, kind="custom")
    damper_dof: int | tuple | None = param(None, kind="whole", many=True)
    force_dof: int | None = param(None, kind="whole")
    response_dof: int | None = param(None, kind="whole")
    rayleigh: tuple | None = param(None, kind="list")
    damping_ratio: float | None = param(None, kind="number")
    modes_kept: int | None = param(None, kind="whole")
    rayleigh_modes: tuple | None = param(None, kind="list")
    rayleigh_ratios: tuple | None = param(None, kind="list")


@register_drive
@dataclass(frozen=True, kw_only=True)
class ModalStructure(StructureBase, _Modes):
    """The container rides on a structure of N modes, two-way coupled (docs/structure.md).

    Each mode k (modal mass m_k, natural frequency f_k, damping ratio zeta_k, mode shape phi_k at
    the damper, the force and the response point, along the drive direction) obeys

        m_k q_k'' + c_k q_k' + k_k q_k = phi_k(force) F0 sin(2 pi f_F t) - phi_k(damper) F_w,

    ``k_k = m_k (2 pi f_k)^2``, ``c_k = 2 zeta_k sqrt(k_k m_k)``; the container moves with the damper
    point, ``x_c = sum_k phi_k(damper) q_k``; the response point with ``sum_k phi_k(response) q_k``.

    The modes are given either as ``modes`` (a list of tables ``{frequency, damping_ratio,
    modal_mass, damper, force, response}``) or computed from FE matrices ``matrices`` (an .npz with
    arrays ``M``, ``K`` and optionally ``C``, or a table of Matrix Market / Harwell-Boeing files)
    with ``damper_dof``, ``force_dof``, ``response_dof`` (0-based indices), the damping as
    ``rayleigh = [alpha, beta]`` (C = alpha M + beta K), ``rayleigh_modes = [i, j]`` with
    ``rayleigh_ratios = [zeta_i, zeta_j]`` (the Rayleigh damping with those ratios at modes i and
    j), ``damping_ratio`` (every mode) or the file's ``C`` (its modal projection's diagonal), and
    ``modes_kept`` (the lowest modes of the generalised problem K phi = omega^2 M phi,
    mass-normalised; default all): :mod:`pdamper.structure.matrices`.

    The truncation error (:attr:`truncation_error`) is the relative error of the static compliance
    at the damper dof from the kept modes, ``sum_k phi_k(d)^2 / omega_k^2``, against ``(K^-1)_dd``.

    ``displacement`` and ``velocity`` are the damper point's at t = 0, taken in the static shape of
    a load at the damper (``q_k proportional to phi_k(damper) / k_k``: the structure pulled at the
    damper and released).

    Examples
    --------
    >>> s = ModalStructure(modes=({"frequency": 2.0, "damping_ratio": 0.005, "modal_mass": 7.0,
    ...                            "damper": 1.0, "force": 1.0, "response": 1.0},), displacement=0.01)
    >>> round(s.natural_frequency, 3), s.n_modes
    (2.0, 1)
    """

    kind: str = param("modal", kind="tag")
    config_marks = ("modes", "matrices")
    damper_points_key = ("dof", "damper_dof")
    config_label = "a structure of several modes"
    config_summary = "modes = [...] or matrices = ... (several modes)"

    def __post_init__(self):
        self._prepare()
        self._check_scales()
        given = [k for k in ("modes", "matrices") if getattr(self, k)]
        if len(given) != 1:
            raise InputError("structure: give exactly one of modes = [{frequency, damping_ratio, modal_mass, damper, "
                             "force, response}, ...] or matrices = 'frame.npz'" +
                             (" (both are given)" if len(given) == 2 else ""))
        if self.modes:
            extra = [k for k in _FE_KEYS if getattr(self, k) is not None]
            if extra or self.damping_ratio is not None:
                k = extra[0] if extra else "damping_ratio"
                raise InputError(f"structure.{k} belongs to matrices = ...; with modes each mode has its own "
                                 "damping_ratio and mode shape values (damper, force, response)")
            if isinstance(self.modes, dict) or not hasattr(self.modes, "__len__"):
                raise InputError("structure.modes: give a list of tables, modes = [{frequency = '2Hz', ...}, ...]")
            modes = tuple(_read_mode(m, k) for k, m in enumerate(self.modes))
            object.__setattr__(self, "modes", modes)
            data = {key: np.array([m[key] for m in modes]) for key in _MODE_KEYS}
            data["truncation_error"] = math.nan
            data["shapes"] = None
        else:
            if self.rayleigh_modes is not None:
                object.__setattr__(self, "rayleigh_modes", tuple(int(v) if float(v).is_integer() else v
                                                                 for v in self.rayleigh_modes))
            if isinstance(self.damper_dof, tuple):
                object.__setattr__(self, "damper_dof", self.damper_dof[0] if len(self.damper_dof) == 1
                                   else tuple(self.damper_dof))
            data = modes_from_matrices(self)
        self._set_modal(data, "modes" if self.modes else "modes_kept")

    def _set_modal(self, data: dict, key: str) -> None:
        """Keep the modal ``data`` (:func:`~pdamper.structure.matrices.modes_from_matrices`'s, or of
        modes given as data), check the highest mode (``key`` names what sets it) and what moves the
        structure."""
        if self.stiffness_scale != 1.0 or self.mass_scale != 1.0:
            # K and M scaled: the same shapes, modal masses times mass_scale, frequencies times
            # sqrt(stiffness_scale / mass_scale), the damping ratios as they were
            data["modal_mass"] = data["modal_mass"] * self.mass_scale
            data["frequency"] = data["frequency"] * math.sqrt(self.stiffness_scale / self.mass_scale)
            if data.get("mass_shapes") is not None:
                data["mass_shapes"] = data["mass_shapes"] * self.mass_scale
        # the modes as given (or computed): every dof's shape, a ground load's participation and
        # the container's mass carried later are taken in them (carrying: basis)
        data.setdefault("dampers", data["damper"][None, :].copy())
        data.update(basis=np.eye(data["frequency"].size), damper0=data["damper"].copy(),
                    dampers0=data["dampers"].copy(), modal_mass0=data["modal_mass"].copy())
        object.__setattr__(self, "_modal", data)
        object.__setattr__(self, "_carried", np.zeros(data["dampers"].shape[0]))
        top = float(np.max(data["frequency"]))
        if top > MODE_LIMIT_HZ:
            raise InputError(f"structure.{key}: a mode at {top:.4g} Hz; keep modes below {MODE_LIMIT_HZ:g} Hz (the "
                             "structure's step is explicit in the stiffness: stable for omega h < 2, and Gear's steps "
                             f"reach {_GEAR_STEP_BOUND * 1e6:g} us)" + (", e.g. modes_kept = 4" if key == "modes_kept"
                                                                      else ""))
        self._check_motion()
        self._check_dofs()

    @classmethod
    def config_read_extra(cls, table: dict, base_dir) -> dict:
        """``modes`` as given (each entry read by the model), ``matrices`` with its file names made
        absolute (relative to the config file: a case written elsewhere still finds them)."""
        kw = super().config_read_extra(table, base_dir)
        if "modes" in table:
            kw["modes"] = table["modes"]
        if "matrices" in table:
            def path(value):
                return str(resolved(value, base_dir))

            m = table["matrices"]
            if isinstance(m, str):
                m = path(m)
            elif isinstance(m, dict):
                m = {k: (path(v) if isinstance(v, str) else v) for k, v in m.items()}
            kw["matrices"] = m
        return kw

    def carrying(self, mass):
        """The structure with the empty container's ``mass`` [kg] rigidly at the damper (several
        dampers: at each, one mass for all or a sequence of one per damper): the modal equations
        coupled by it, ``(diag m + sum_j m_j phi_j phi_j^T) q'' + diag c q' + diag k q = ...``,
        diagonalised again (the kept modes' subspace; the dashpots projected on the new modes'
        diagonal, as a C matrix is). Itself for no mass."""
        masses = np.broadcast_to(np.asarray(mass, dtype=float), self._carried.shape).copy()
        if not np.any(masses):
            return self
        from scipy.linalg import eigh

        m, k, c, pd, pf, pr = self._modal_arrays()
        P = self._modal["dampers"]
        M = np.diag(m) + sum(mj * np.outer(pj, pj) for mj, pj in zip(masses, P))
        w2, psi = eigh(np.diag(k), M)  # psi^T M psi = 1
        w = np.sqrt(w2)
        c_new = np.einsum("ik,i,ik->k", psi, c, psi)
        data = dict(self._modal, frequency=w / (2.0 * math.pi), damping_ratio=c_new / (2.0 * w),
                    modal_mass=np.ones(w.size), damper=pd @ psi, force=pf @ psi, response=pr @ psi,
                    dampers=P @ psi, basis=self._modal["basis"] @ psi)
        new = copy.copy(self)
        new.__dict__.pop("_bare_peaks", None)
        object.__setattr__(new, "_modal", data)
        object.__setattr__(new, "_carried", self._carried + masses)
        return new

    @property
    def damper_count(self) -> int:
        """The dampers on the structure: one, or one at each dof of ``damper_dof = [2, 1]``."""
        return int(self._modal["dampers"].shape[0])

    def at_damper(self, k: int):
        """The structure with its damper point ``k`` (of ``damper_dof = [..]``) as its one damper."""
        dofs = self.damper_dof if isinstance(self.damper_dof, tuple) else (self.damper_dof,)
        if not 0 <= k < self.damper_count or self.damper_dof is None:
            return super().at_damper(k)
        return dataclasses.replace(self, damper_dof=dofs[k])

    def damper_shapes(self) -> np.ndarray:
        """(dampers, modes): the mode shapes at every damper point, in the modes as the structure
        runs (the first row is the damper of :meth:`modal_arrays`)."""
        return self._modal["dampers"].copy()

    # -- the modal data ------------------------------------------------------------------
    @property
    def mode_frequencies(self) -> np.ndarray:
        """f_k [Hz]."""
        return self._modal["frequency"].copy()

    @property
    def mode_damping_ratios(self) -> np.ndarray:
        """zeta_k [-], each mode's damping ratio (given, or from the matrices' damping)."""
        return np.asarray(self._modal["damping_ratio"], dtype=float).copy()

    @property
    def truncation_error(self) -> float:
        """Relative error of the static compliance at the damper dof from the kept modes against the
        full ``(K^-1)_dd`` (matrices only; NaN for modes given as data)."""
        return float(self._modal["truncation_error"])

    def _modal_arrays(self):
        m = self._modal
        mass = m["modal_mass"]
        w = 2.0 * math.pi * m["frequency"]
        k = mass * w * w
        c = 2.0 * m["damping_ratio"] * np.sqrt(k * mass)
        return mass, k, c, m["damper"], m["force"], m["response"]

    def modal_arrays(self):
        """(modal masses m_k [kg], stiffnesses k_k [N/m], dampings c_k [N s/m], mode shapes at the
        damper, at the force, at the response point), arrays over the modes."""
        return tuple(np.array(a, dtype=float) for a in self._modal_arrays())

    @property
    def mass(self) -> float:
        """The first mode's mass seen at the damper, m_1 / phi_1(damper)^2 [kg] (the equivalent
        single-mode structure at the damper)."""
        return float(self._modal["modal_mass"][0] / self._modal["damper"][0] ** 2)

    @property
    def natural_frequency(self) -> float:
        """f_1 [Hz], the lowest mode (without the bed)."""
        return float(self._modal["frequency"][0])

    @property
    def stiffness(self) -> float:
        """The first mode's stiffness at the damper, mass (2 pi f_1)^2 [N/m]."""
        return self.mass * (2.0 * math.pi * self.natural_frequency) ** 2

    @property
    def damping(self) -> float:
        """c = 2 zeta_1 sqrt(K M) [N s/m] of the first mode at the damper."""
        return 2.0 * self.modal_damping_ratio * math.sqrt(self.stiffness * self.mass)

    def initial_modes(self):
        """(q_k(0), q_k'(0)): the damper point at ``displacement`` and ``velocity`` in the static
        shape of a load at the damper, ``q_k proportional to phi_k(damper) / k_k``."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        shape = pd / k
        unit = float(np.sum(pd * shape))
        return shape * (self.displacement / unit), shape * (self.velocity / unit)

    @property
    def velocity_bound(self) -> float:
        """An upper estimate [m/s] of the damper point's speed without the bed (for the time step)."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        q0, v0 = self.initial_modes()
        w = np.sqrt(k / mass)
        free = float(np.sum(np.abs(pd) * (np.abs(v0) + w * np.abs(q0))))
        forced = 0.0
        if self.force_amplitude > 0:
            wf = 2.0 * math.pi * self.force_frequency
            zeta = np.maximum(self._modal["damping_ratio"], 0.01)
            res = np.abs(pd * pf) * self.force_amplitude / k / (2.0 * zeta)
            forced = float(np.sum(np.maximum(wf, w) * res))
        return free + 2.0 * forced

    def modal_motion(self, t):
        """(q, q', q'') [each (N, len(t))] of the modes *without* the bed (closed form per mode)."""
        from ..theory.oscillator import oscillator_response

        mass, k, c, pd, pf, pr = self._modal_arrays()
        q0, v0 = self.initial_modes()
        out = [oscillator_response(t, mass=mass[j], stiffness=k[j], damping_ratio=self._modal["damping_ratio"][j],
                                   force_amplitude=pf[j] * self.force_amplitude,
                                   force_frequency=self.force_frequency or 0.0, displacement=q0[j], velocity=v0[j])
               for j in range(self.n_modes)]
        return tuple(np.array([np.asarray(o[i], dtype=float) for o in out]) for i in range(3))

    def motion(self, t):
        """(x, v, a) of the damper point at times t [s] *without* the bed (modal superposition of
        the closed forms; under a load in time the exact linear response,
        :mod:`pdamper.structure.linear`); the coupled motion is recorded by the run."""
        if self.load is not None:
            from .linear import damper_motion

            return damper_motion(self, t)
        pd = self._modal["damper"]
        return tuple(np.tensordot(pd, z, axes=1) for z in self.modal_motion(t))

    def response_motion(self, t):
        """Displacement [m] of the response point at times t [s] without the bed (closed form)."""
        return np.tensordot(self._modal["response"], self.modal_motion(t)[0], axes=1)

    def steady_amplitude(self, frequencies, force_amplitude: float, added_mass: float = 0.0, point: str = "damper"):
        """Steady amplitude [m] at the damper (or ``point = "response"``) under ``force_amplitude``
        sin(2 pi f t) at each of ``frequencies`` [Hz], without the bed; ``added_mass`` [kg] rigidly
        at the damper (the bed as a solid mass): the modal equations coupled by it,
        ``(-W^2 (diag m + m_a phi_d phi_d^T) + i W diag c + diag k) q = phi_f F0``: the magnitude of
        :meth:`~pdamper.structure.base.StructureBase.steady_phasor`."""
        return np.array([abs(complex(z)) for z in self.steady_phasor(frequencies, force_amplitude, added_mass, point)])

    def kernel_drive(self):
        """(kernel kind, par, table, state) for the kernels (:func:`pdamper.kernels.structure.modal_step`);
        the state starts at rest at the initial shape (held during settling); under a load in time
        :meth:`load_kernel_drive`."""
        if self.load is not None:
            return self.load_kernel_drive()
        mass, k, c, pd, pf, pr = self._modal_arrays()
        om = 2.0 * math.pi * (self.force_frequency or 0.0)
        par = np.array([self.force_amplitude, om])
        tab = np.ascontiguousarray(np.column_stack([mass, k, c, pd, pf, pr]))
        return "modal", par, tab, self._held_state(pd, pr)

    def start_state(self, st, wall_force: float = 0.0) -> float:
        """Release at t = 0: the modes at (q0, q0'), accelerations from the modal equations with
        ``wall_force`` [N] at the damper; returns the damper point's a0."""
        if self.load is not None:
            return self.load_start_state(st, wall_force)
        mass, k, c, pd, pf, pr = self._modal_arrays()
        q0, v0 = self.initial_modes()
        a = (-c * v0 - k * q0 - pd * wall_force) / mass
        st[:, :] = 0.0
        st[2:, 0], st[2:, 1], st[2:, 2] = q0, v0, a
        st[0, 0:5] = (float(np.dot(pd, q0)), float(np.dot(pd, v0)), float(np.dot(pd, a)), 0.0, float(np.dot(pf, v0)))
        st[1, 2] = float(np.dot(pr, q0))
        return float(st[0, 2])

    def initial_modal_state(self):
        """(q_k(0), q_k'(0)): :meth:`initial_modes`."""
        return self.initial_modes()

    def dof_shapes(self):
        """(labels, shapes): matrices: every dof of the FE model (labels 0 .. n - 1, 0-based as
        ``damper_dof``), its rows of the kept mode shapes; modes given as data: the damper, force and
        response points (labels ``"damper"``, ``"force"``, ``"response"``). In the modes as the
        structure runs (with the container's mass carried)."""
        m = self._modal
        if m["shapes"] is not None:
            return self._named(list(m["labels"] if "labels" in m else range(m["shapes"].shape[0]))), \
                m["shapes"] @ m["basis"]
        return self._named(["damper", "force", "response"]), np.vstack([m["damper"], m["force"], m["response"]])

    def ground_participation(self, influence=None, participation=None) -> np.ndarray:
        """L_k of each mode as the structure runs: matrices: ``phi_k^T M r`` with the influence
        vector r (``influence``: per dof, or one node's pattern repeated over the nodes; default 1 at
        every dof), or ``Gamma_k m_k`` with ``participation``; modes given as data need
        ``participation``. The container's carried mass m_c at the damper adds ``m_c phi_k(d) r_d``
        (r_d = 1 with ``participation``)."""
        m = self._modal
        n_modes = m["basis"].shape[0]
        if participation is not None:
            g = np.asarray(participation, dtype=float)
            if g.shape != (n_modes,):
                raise InputError(f"load.participation has {g.size} value{'s' if g.size != 1 else ''}; the structure "
                                 f"has {n_modes} mode{'s' if n_modes != 1 else ''}: give one Gamma_k per mode")
            L0, r_d = g * m["modal_mass0"], np.ones(self._carried.size)
        else:
            if m["shapes"] is None:
                raise InputError("load.participation is missing: a structure of modes given as data needs each "
                                 "mode's participation Gamma_k in a ground acceleration, e.g. participation = [1.3] "
                                 "(FE matrices give it from the mass matrix)")
            n = m["shapes"].shape[0]
            r = np.ones(n)
            if influence is not None:
                pattern = np.asarray(influence, dtype=float)
                if pattern.size == 0 or n % pattern.size:
                    raise InputError(f"load.influence has {pattern.size} values; give one per dof ({n}) or the "
                                     f"pattern of one node's dofs (a divisor of {n}, e.g. [1, 0])")
                r = np.tile(pattern, n // pattern.size)
            L0 = m["mass_shapes"] @ r
            r_d = r[m["damper_index"]]
        # the containers' masses carried at the dampers (the same products, in the same order, as one)
        return m["basis"].T @ (L0 + sum(mj * pj * float(rj) for mj, pj, rj in zip(self._carried, m["dampers0"], r_d)))

    @property
    def initial_energy(self) -> float:
        """Mechanical energy of the structure at t = 0 [J]."""
        mass, k, c, pd, pf, pr = self._modal_arrays()
        q0, v0 = self.initial_modes()
        return float(np.sum(0.5 * mass * v0**2 + 0.5 * k * q0**2))

    def record_info(self) -> dict:
        """What :class:`pdamper.recorders.structure.StructureRecord` keeps of the structure."""
        return {"mass_kg": self.mass, "stiffness_N_m": self.stiffness, "x0_m": self.displacement,
                "v0_m_s": self.velocity, "initial_energy_J": self.initial_energy}

    def structure_summary(self) -> dict:
        """Plain numbers about the structure for a run's summary: the modes, and with matrices the
        truncation error (:attr:`truncation_error`) and the number of dofs."""
        out = {"modes_kept": self.n_modes, "mode_frequencies_hz": self.mode_frequencies.tolist(),
               "mode_damping_ratios": self.mode_damping_ratios.tolist()}
        if self.matrices:
            out.update(truncation_error=self.truncation_error, dofs=int(self._modal["dofs"]))
        return out

    def config_extra(self) -> dict:
        """The keys a config file needs beyond the plain fields: ``modes`` or ``matrices``."""
        if self.modes:
            return {"modes": [dict(m) for m in self.modes], **super().config_extra()}
        m = self.matrices
        return {"matrices": {k: str(v) for k, v in m.items()} if isinstance(m, dict) else str(m),
                **super().config_extra()}

    def describe(self) -> str:
        fs = ", ".join(f"{f:.4g}" for f in self.mode_frequencies[:4]) + (", ..." if self.n_modes > 4 else "")
        total = float(np.sum(self._carried))
        carried = (f", carrying the container's {total:g} kg" if self._carried.size == 1 else
                   f", carrying the containers' {', '.join(f'{m:g}' for m in self._carried)} kg") if total else ""
        return (f"modal structure, {self.n_modes} mode{'s' if self.n_modes > 1 else ''} ({fs} Hz){carried}, "
                f"{self._forced_words()}")
