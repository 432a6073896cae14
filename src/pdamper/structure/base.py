"""What every structure model shares: the fields that move it (a harmonic force, a start), its
direction, and the answers of the drive protocol that follow from its modes.

A structure is a drive (:class:`pdamper.excitation.DriveBase`) of the ``[structure]`` section
whose motion the bed's force changes (``coupled``). A model (:mod:`.sdof`, :mod:`.modal`) is a
frozen dataclass made of two parts: its own fields, in a small dataclass listed *last* among its
bases, and :class:`StructureBase`'s shared ones. Python collects a dataclass's fields from the
last base to the first, so the model's own fields come first and the shared ones after: the
order of the keys a config file is written in, which a result store's fingerprint is taken of
(``tests/structure/test_base.py`` checks the written text is the one pdamper wrote before the
shared base).

What a model adds to the drive protocol (:class:`StructureBase` derives the rest from it):

=============================  ==================================================================
``modal_arrays()``             (m_k, k_k, c_k, phi_k(damper), phi_k(force), phi_k(response))
``mode_frequencies``           f_k [Hz], the lowest first; ``mode_damping_ratios`` zeta_k [-]
``natural_frequency``          f_1 [Hz]; ``mass``, ``stiffness``, ``damping``: the first mode's at the
                               damper [kg, N/m, N s/m]
``steady_amplitude(f, F0)``    the steady amplitude without the bed (closed form)
``start_state(st, F_w)``       releases it at t = 0 in the kernels' state
``carrying(mass)``             the structure with the empty container's mass at the damper
``record_info()``              what the run's structure record keeps
``structure_summary()``        plain numbers for a run's summary
``dof_shapes()``               (dof labels, the mode shapes at every dof): every dof's motion
``ground_participation(...)``  L_k = phi_k^T M r of each mode (a ground acceleration's load)
=============================  ==================================================================

**Loads.** What moves a structure is its harmonic force (``force_amplitude``,
``force_frequency``), its start (``displacement``, ``velocity``) or a load in time (``load``, a
:mod:`pdamper.structure.loads` object read from a ``[load]`` section: a force history, a ground
acceleration, a random load, a stepped sine). Under a load in time the kernels take the modal
equations with the load's table (kernel kind ``"modal_load"``, :mod:`pdamper.kernels.structure`;
one mode as a modal structure of one mode, every shape 1), the run lasts the load's
:attr:`~pdamper.structure.loads.base.LoadBase.duration`, and the structure without the bed has its
exact linear solution (:mod:`pdamper.structure.linear`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, shown
from ..excitation import DriveBase
from ..schema import param
from ..units import thousandth_hint

__all__ = ["StructureBase", "MAX_STRUCTURE_HZ", "SCALES"]

#: Highest natural or forcing frequency of a structure [Hz].
MAX_STRUCTURE_HZ = 1000.0
#: The range of ``stiffness_scale`` and ``mass_scale``: a model off by a factor, not another structure.
SCALES = (0.01, 100.0)


@dataclass(frozen=True, kw_only=True)
class StructureBase(DriveBase):
    """The fields every structure has, and the drive protocol's answers shared by the models.

    Parameters
    ----------
    force_amplitude : float
        F0 [N], >= 0 (0: free motion), of the harmonic force ``F0 sin(2 pi f_F t)``.
    displacement, velocity : float
        The damper point's x [m] and v [m/s] when the drive starts (t = 0).
    angle : float
        Direction of the motion in the horizontal plane [rad], as for
        :class:`~pdamper.excitation.HarmonicDrive`.
    force_frequency : float or None
        f_F [Hz], > 0, needed when F0 > 0.
    direction : (x, y, z) or None
        Direction of the motion in the lab frame (y up), instead of ``angle``.
    stiffness_scale, mass_scale : float
        > 0 (default 1): K and M of the model times these (a frame 10 % softer than its model:
        ``stiffness_scale = 0.9``; an ensemble's unknowns, docs/ensembles.md). Every mode's
        frequency moves by sqrt(stiffness_scale / mass_scale), its modal mass by mass_scale; the
        mode shapes and the damping ratios stay as given. The fields ``mass`` and ``stiffness`` of a
        single mode, the modes given as data and the matrices stay as given (and are written so,
        with the scales beside); what runs (:meth:`carrying`) has them taken in. From 0.01 to 100
        (:data:`SCALES`).
    coupling_step : float or None
        The coupling loop's step [s] (several dampers, a co-simulation: :mod:`pdamper.cosim`); None:
        the case's sample interval.
    """

    force_amplitude: float = param(0.0, dimension="force")
    displacement: float = param(0.0, dimension="length")
    velocity: float = param(0.0, dimension="velocity")
    angle: float = param(0.0, dimension="angle")
    force_frequency: float | None = param(None, dimension="frequency")
    direction: tuple | None = param(None, kind="list")
    load: object = param(None, kind="custom")
    #: the dofs' names and the storeys (:mod:`.storeys`), written only when given
    dof_names: tuple | None = param(None, kind="custom")
    storey_heights: tuple | None = param(None, kind="list", dimension="length")
    storey_height: float | None = param(None, dimension="length")
    storey_dofs: tuple | None = param(None, kind="custom")
    stiffness_scale: float = param(1.0, dimension="dimensionless", write_default=False)
    mass_scale: float = param(1.0, dimension="dimensionless", write_default=False)
    #: the coupling step of the coupling loop [s] (several dampers, a co-simulated structure:
    #: :mod:`pdamper.cosim`); None: the case's sample interval
    coupling_step: float | None = param(None, dimension="time", auto=True, write_default=False)

    config_section = "structure"
    coupled = True
    #: how ``[[damper]]`` tables place their dampers: (the table's key, the ``[structure]`` key of the
    #: list of damper points); (None, None): one point, every damper on it
    damper_points_key = (None, None)
    config_writes_kind = False  # a [structure] tells its model by its keys
    config_after = "run"        # [structure] last

    @property
    def counts_cycles(self) -> bool:
        """The run lasts ``[run] cycles`` periods of :attr:`frequency`, except under a load in time
        (its own duration)."""
        return self.load is None

    @classmethod
    def config_read_extra(cls, table: dict, base_dir) -> dict:
        """The load of the case's ``[load]`` section (put in the table by :mod:`pdamper.config`), the
        dofs' names and the storeys' dofs as given (checked by the model: :mod:`.storeys`)."""
        return {k: table[k] for k in ("load", "dof_names", "storey_dofs") if k in table}

    def config_extra(self) -> dict:
        """``dof_names`` and ``storey_dofs`` where given."""
        return {k: list(getattr(self, k)) for k in ("dof_names", "storey_dofs") if getattr(self, k) is not None}

    def config_sections(self) -> dict:
        """The sections written after ``[structure]``: ``[load]`` of a load in time
        (:meth:`~pdamper.structure.loads.base.LoadBase.config_table`)."""
        return {} if self.load is None else {"load": self.load.config_table()}

    # ---- checks
    def _check_scales(self) -> None:
        """``stiffness_scale`` and ``mass_scale``: numbers from :data:`SCALES`' low to its high."""
        lo, hi = SCALES
        for name in ("stiffness_scale", "mass_scale"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not (lo <= v <= hi):
                raise InputError(f"structure.{name} = {shown(v)}; must be a number from {lo:g} to {hi:g}, the model's "
                                 f"{'K' if name == 'stiffness_scale' else 'M'} times it (1: as given; 0.9: 10 % less)")

    def _check_motion(self) -> None:
        """Validate what moves it (``force_amplitude``, ``force_frequency``, ``displacement``,
        ``velocity``, ``load``) and its direction; something must move it."""
        from .loads import LoadBase

        if self.load is not None:
            if not isinstance(self.load, LoadBase):
                raise InputError(f"structure.load = {shown(self.load)}; give the load in a [load] section, e.g. [load] "
                                 "kind = 'force_history', file = 'hammer.csv'")
            if not self.load.in_time:
                raise InputError("structure.load: a harmonic load is the structure's force_amplitude and "
                                 "force_frequency; give those")
            if self.force_amplitude != 0:
                raise InputError(f"structure.force_amplitude = {shown(self.force_amplitude)} N and a [load] both move the "
                                 "structure; give one: force_amplitude = 0 with the [load], or no [load]")
            object.__setattr__(self, "load", self.load.for_structure(self))  # e.g. a record scaled at its period
        f0 = self.force_amplitude
        if isinstance(f0, bool) or not isinstance(f0, (int, float)) or not (f0 >= 0 and math.isfinite(f0)):
            raise InputError(f"structure.force_amplitude = {shown(f0)} N; must be >= 0 (0: free motion)")
        ff = self.force_frequency
        if ff is not None and not (isinstance(ff, (int, float)) and ff > 0 and math.isfinite(ff)):
            raise InputError(f"structure.force_frequency = {shown(ff)} Hz; must be > 0, e.g. '2Hz'")
        if f0 > 0 and ff is None:
            raise InputError("structure.force_frequency is missing: a force_amplitude > 0 needs its "
                             "frequency, e.g. force_frequency = '2Hz'")
        for name in ("displacement", "velocity"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise InputError(f"structure.{name} = {shown(v)}; must be a finite number")
        self._check_direction()
        if f0 == 0 and self.displacement == 0 and self.velocity == 0 and self.load is None:
            raise InputError("structure: nothing moves it; give a displacement (free decay, e.g. '10mm'), "
                             "a force_amplitude with force_frequency (forced response) or a [load] section")

    def check_scale(self, length: float) -> None:
        """A start (``displacement``, ``velocity``) or resonant swing (F0 / K / 2 zeta of the first
        mode) beyond twice the container's ``length`` [m], or a frequency beyond 1 kHz (no damper
        test; the time step would vanish): an InputError with the fix. The model as it runs: its
        scales taken in (:meth:`carrying` of no mass)."""
        model = self.carrying(0.0)
        if not self.natural_frequency <= MAX_STRUCTURE_HZ:
            raise InputError(f"structure: a natural frequency of {self.natural_frequency:.3g} Hz (structure.mass = "
                             f"{model.mass:g} kg, stiffness {model.stiffness:.3g} N/m) is beyond {MAX_STRUCTURE_HZ:g} Hz; "
                             "check structure.mass and structure.stiffness / natural_frequency (a number without a "
                             "unit is SI)")
        ff = self.force_frequency
        if ff is not None and not ff <= MAX_STRUCTURE_HZ:
            raise InputError(f"structure.force_frequency = {ff:g} Hz is beyond {MAX_STRUCTURE_HZ:g} Hz, no damper test; "
                             "give the forcing frequency, e.g. '2Hz'")
        for key in ("displacement", "velocity"):
            v = abs(getattr(self, key))
            limit = 2 * length if key == "displacement" else 2 * length * 2 * math.pi * self.natural_frequency
            if v > limit:
                unit = "m" if key == "displacement" else "m/s"
                raise InputError(f"structure.{key} = {getattr(self, key):g} {unit} moves the container {v / limit:.3g} "
                                 f"times further than twice its length {length:g} m (a number without a unit is SI)"
                                 f"{thousandth_hint(v, limit, 'mm' if key == 'displacement' else 'mm/s')}")
        if self.load is not None:
            peak = self.bare_peaks()[0]
            if not peak <= 2 * length:
                raise InputError(f"[load] {self.load.describe()} would swing the structure's damper point by "
                                 f"{peak:.3g} m without the damper (its exact linear response), beyond twice the "
                                 f"container's length {length:g} m; check [load] {', '.join(self.load.size_keys)} and "
                                 "[structure] mass, stiffness or natural_frequency and damping_ratio (a number without "
                                 "a unit is SI)")
            return
        resonant = self.force_amplitude / model.stiffness / max(2.0 * self.modal_damping_ratio, 0.02)
        if resonant > 2 * length:
            raise InputError(f"structure.force_amplitude = {self.force_amplitude:g} N would swing the structure "
                             f"(structure.mass = {model.mass:g} kg, stiffness {model.stiffness:.3g} N/m) by about "
                             f"{resonant:.3g} m at resonance (F0 / K / 2 zeta), beyond twice the container's length "
                             f"{length:g} m; give a smaller force or check the mass (a number without a unit is SI)")

    # ---- what follows from the modes
    @property
    def frequency(self) -> float:
        """The frequency [Hz] that counts the run's cycles: f_F when forced, else f_1 (under a load in
        time too: the run lasts the load's duration)."""
        return self.force_frequency if self.force_amplitude > 0 else self.natural_frequency

    @property
    def n_modes(self) -> int:
        """Number of modes carried."""
        return int(np.size(self.mode_frequencies))

    @property
    def highest_frequency(self) -> float:
        """The highest frequency of the structure's motion without the bed [Hz] (for time steps)."""
        load = self.load.highest_frequency if self.load is not None else 0.0
        return float(max(np.max(self.mode_frequencies), self.force_frequency or 0.0, load))

    @property
    def modal_damping_ratio(self) -> float:
        """zeta_1 [-] of the first mode."""
        return float(self.mode_damping_ratios[0])

    def duration(self, cycles: float) -> float:
        """Time [s] of ``cycles`` periods of :attr:`frequency`; under a load in time its duration."""
        if self.load is not None:
            return self.load.duration
        return cycles / self.frequency

    def speed_bound(self) -> float:
        """An upper estimate [m/s] of the container's speed (``velocity_bound``); under a load in
        time the damper point's largest speed without the bed (its exact linear response), the
        ground's speed added under a ground acceleration (the bed sees the container's absolute
        motion)."""
        if self.load is not None:
            return self.bare_peaks()[1]
        return self.velocity_bound

    # ---- under a load in time
    def bare_peaks(self) -> tuple[float, float]:
        """(largest |x| [m], largest |v| [m/s] with the ground's speed under a ground acceleration) of
        the damper point without the bed under the load (exact linear response, sampled at 20 points
        a period of the highest mode or the load's top frequency, up to 5 periods of the lowest mode
        after the load's end; cached)."""
        cached = self.__dict__.get("_bare_peaks")
        if cached is not None:
            return cached
        from .linear import ground_velocity, modal_response

        fmax = max(float(np.max(self.mode_frequencies)), self.load.highest_frequency)
        # after the load's last row the structure rings down: its largest swing comes within a few
        # periods of the lowest mode (a duration far beyond them adds nothing)
        end = self.load.kernel_table()[1][-1, 0] + 5.0 / float(np.min(self.mode_frequencies))
        span = min(self.load.duration, end)
        n = int(min(2_000_000, max(2, math.ceil(span * 20.0 * fmax))))
        t = np.linspace(0.0, span, n + 1)
        q, qd = modal_response(self, t)
        pd = self.modal_arrays()[3]
        x, v = q @ pd, qd @ pd
        vg = float(np.max(np.abs(ground_velocity(self.load, t)))) if self.load.ground else 0.0
        out = (float(np.max(np.abs(x))), float(np.max(np.abs(v))) + vg)
        object.__setattr__(self, "_bare_peaks", out)
        return out

    def initial_modal_state(self):
        """(q_k(0), q_k'(0)) of the modes at the start (one mode: x0, v0)."""
        return np.array([float(self.displacement)]), np.array([float(self.velocity)])

    def load_kernel_drive(self):
        """(``"modal_load"``, par, table, state) of the structure under its load in time
        (:func:`pdamper.kernels.structure.loaded_step`): par = (form, ground), the table's rows
        (m_k, k_k, c_k, phi_k(damper), phi_k(force), phi_k(response), b_k); the state at rest at
        the initial shape (held during settling)."""
        mass, k, c, pd, pf, pr = self.modal_arrays()
        b = self.load.modal_coefficients(self)
        form, _ = self.load.kernel_table()
        par = np.array([float(form), 1.0 if self.load.ground else 0.0])
        tab = np.ascontiguousarray(np.column_stack([mass, k, c, pd, pf, pr, b]))
        return "modal_load", par, tab, self._held_state(pd, pr)

    def _held_state(self, pd, pr) -> np.ndarray:
        """The kernels' state of the modes (2 + N rows) at rest at the initial shape, held during
        settling: q_k(0), the damper point's and the response point's displacement."""
        st = np.zeros((2 + self.n_modes, 5))
        q0, _ = self.initial_modal_state()
        st[2:, 0] = q0
        st[0, 0] = float(np.dot(pd, q0))
        st[1, 2] = float(np.dot(pr, q0))
        return st

    def kernel_load(self):
        """The kernels' rows of the load in time (:attr:`pdamper.kernels.bundles.Drive.load`);
        none (one row of zeros) without one."""
        if self.load is None:
            return np.zeros((1, 4))
        return np.ascontiguousarray(self.load.kernel_table()[1])

    def load_start_state(self, st, wall_force: float = 0.0) -> float:
        """Release under the load at t = 0: the modes at (q0, q0'), accelerations with the load's
        f(0) and ``wall_force`` [N] at the damper; returns the damper point's a0 (relative to the
        ground)."""
        mass, k, c, pd, pf, pr = self.modal_arrays()
        b = self.load.modal_coefficients(self)
        f0 = float(self.load.values(np.array([0.0]))[0])
        q0, v0 = self.initial_modal_state()
        a = (b * f0 - c * v0 - k * q0 - pd * wall_force) / mass
        st[:, :] = 0.0
        st[2:, 0], st[2:, 1], st[2:, 2] = q0, v0, a
        st[0, 0:5] = (float(np.dot(pd, q0)), float(np.dot(pd, v0)), float(np.dot(pd, a)), f0, float(np.dot(b, v0)))
        st[1, 2] = float(np.dot(pr, q0))
        st[1, 3] = f0 if self.load.ground else 0.0
        return float(st[0, 2])

    # ---- the dampers on it
    @property
    def damper_count(self) -> int:
        """The damper points on the structure (one mode: one, its own dof; FE matrices: one at each
        dof of ``damper_dof = [2, 1]``)."""
        return 1

    def damper_shapes(self) -> np.ndarray:
        """(damper points, modes): the mode shapes at every damper point in the modes as the
        structure runs; the first row is the damper of :meth:`modal_arrays`."""
        return self.modal_arrays()[3][None, :].copy()

    def at_damper(self, k: int):
        """The structure with its damper point ``k`` as its one damper (a design for one of its modes
        there); one point: itself."""
        if k != 0:
            raise InputError(f"damper point {k + 1}: the structure has one damper point")
        return self

    @property
    def cosimulated(self) -> bool:
        """Whether another code advances the structure (an OpenSees model with its own integrator
        and materials: :mod:`pdamper.cosim`), not pdamper's compiled modal step."""
        return False

    def backend(self, step: float, duration: float, points, masses):
        """The structure advanced a coupling step at a time (:mod:`pdamper.structure.backend`):
        pdamper's own linear modes, exactly between the steps, the dampers at ``points`` (indices
        of :meth:`damper_shapes`) carrying the empty containers' ``masses`` [kg]."""
        from .backend import LinearBackend

        return LinearBackend(self, step=step, duration=duration, points=points, masses=masses)

    # ---- every dof
    def dof_shapes(self):
        """(labels, shapes): the dofs of the structure and the mode shapes there (dofs x modes),
        in the modes as the structure runs (with the empty container's mass). One mode: its one
        dof (label 0, or its ``dof_names``' name), shape 1."""
        return self._named([0]), np.ones((1, 1))

    def _named(self, labels: list) -> list:
        """The dofs' labels: ``dof_names`` where given, else ``labels`` (the model's)."""
        return list(self.dof_names) if self.dof_names is not None else labels

    def _check_dofs(self) -> None:
        """Last in ``__post_init__`` (the dofs known): ``dof_names`` one per dof, the storeys'
        keys (:mod:`.storeys`)."""
        from .storeys import check_dof_names

        names = self.dof_names
        object.__setattr__(self, "dof_names", None)  # the model's own dofs first, to count them
        object.__setattr__(self, "dof_names", check_dof_names(names, len(self.dof_shapes()[0])))
        if isinstance(self.storey_dofs, list):
            object.__setattr__(self, "storey_dofs", tuple(self.storey_dofs))
        self.storeys()  # checks the storeys' keys

    def storeys(self):
        """The storeys' chain (:class:`~pdamper.structure.storeys.Storeys`: the floors' dofs and the
        storeys' heights, from ``storey_heights`` or ``storey_height`` and ``storey_dofs``), or None
        where no height is given."""
        from .storeys import storeys_of

        return storeys_of(self.dof_shapes()[0], self.storey_heights, self.storey_height, self.storey_dofs)

    def ground_participation(self, influence=None, participation=None) -> np.ndarray:
        """L_k [kg] of each mode: the generalised force of a ground acceleration a_g is ``-L_k a_g``.
        One mode: the whole mass, L = M (``participation`` = [Gamma]: Gamma M; ``influence`` = [r]:
        r M)."""
        for key, v in (("influence", influence), ("participation", participation)):
            if v is not None and len(v) != 1:
                raise InputError(f"load.{key} = {shown(list(v))}: the structure has one mode and one dof; give one value")
        g = participation[0] if participation is not None else (influence[0] if influence is not None else 1.0)
        return np.array([g * float(self.modal_arrays()[0][0])])

    def dof_phasors(self, frequencies, force_amplitude: float, added_mass: float = 0.0):
        """Complex steady amplitudes [m] (frequencies x dofs) of every dof under ``force_amplitude``
        sin(2 pi f t) at the force point, without the bed, ``added_mass`` [kg] rigidly at the damper
        (as :meth:`steady_phasor`)."""
        mass, k, c, pd, pf, pr = self.modal_arrays()
        _, shapes = self.dof_shapes()
        out = []
        for f in np.atleast_1d(np.asarray(frequencies, dtype=float)):
            w = 2.0 * math.pi * f
            A = np.diag(k - w * w * mass + 1j * w * c) - w * w * added_mass * np.outer(pd, pd)
            out.append(shapes @ np.linalg.solve(A, pf * force_amplitude))
        return np.array(out)

    def container_motion(self, t: float, state):
        """The damper point's ``(x, v, a)`` now, from the kernels' state."""
        return state[0, 0], state[0, 1], state[0, 2]

    def steady_phasor(self, frequencies, force_amplitude: float, added_mass: float = 0.0, point: str = "damper"):
        """Complex steady amplitude x^ [m] at the damper (or ``point = "response"``) under
        ``force_amplitude`` sin(2 pi f t) at each of ``frequencies`` [Hz] without the bed
        (``x(t) = Im(x^ e^{i 2 pi f t})``: its angle is the phase against the force), with
        ``added_mass`` [kg] rigidly at the damper: ``(-W^2 (diag m + m_a phi_d phi_d^T) + i W diag c +
        diag k) q = phi_f F0``; ``|x^|`` is :meth:`steady_amplitude`."""
        mass, k, c, pd, pf, pr = self.modal_arrays()
        out = []
        for f in np.atleast_1d(np.asarray(frequencies, dtype=float)):
            w = 2.0 * math.pi * f
            A = np.diag(k - w * w * mass + 1j * w * c) - w * w * added_mass * np.outer(pd, pd)
            q = np.linalg.solve(A, pf * force_amplitude)
            out.append(complex(np.dot(pr if point == "response" else pd, q)))
        return np.array(out)

    def _forced_words(self) -> str:
        if self.load is not None:
            return self.load.describe()
        return (f"F0 = {self.force_amplitude:g} N at {self.force_frequency:g} Hz" if self.force_amplitude > 0
                else f"free decay from {self.displacement * 1e3:g} mm")
