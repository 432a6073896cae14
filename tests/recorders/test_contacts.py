"""The ledger by contact type and the contacts channel (pdamper.recorders.contacts, issue 42)."""

from __future__ import annotations

import numpy as np
import pytest

from dem_fixtures import R, TINY_CONFIG, sphere_mass, still_case
from pdamper import run_case
from pdamper.config import loads_case
from pdamper.recorders.base import check_recorders
from pdamper.recorders.contacts import (CONTACT_TYPES, ContactEnergyRecorder, ContactsRecorder, coordination_number)
from pdamper.simulation import Simulation

G = 9.81


def _baffled(**over):
    """The tiny damper (8 spheres, 3 cycles) with a baffle across the middle, struck hard enough that
    every contact type dissipates: sphere pairs, the floor, the end walls, the baffle."""
    return loads_case(TINY_CONFIG, {"container.baffles": [{"position": "0mm"}], "drive.stroke": "20mm", **over})


@pytest.mark.slow
@pytest.mark.parametrize("over", [{"numerics.integrator": "verlet"}, {"numerics.integrator": "gear"},
                                  {"numerics.integrator": "verlet", "contact.tangential": "spring"}],
                         ids=["verlet", "gear", "verlet-spring"])
def test_the_ledger_by_contact_type_sums_to_the_ledger_and_leaves_the_motion_alone(over):
    case = _baffled(**over)
    res = run_case(case, recorders=[ContactEnergyRecorder()])
    split = res.recorded["energy_by_contact"]
    e = res.energy
    assert split.types == CONTACT_TYPES == ("sphere", "floor", "wall", "baffle")
    assert split.damping.shape == (e.time.size, 4) and np.array_equal(split.time, e.time)
    # the parts sum to the totals, to rounding (each type integrated as the totals are)
    scale = e.damping[-1] + e.friction[-1]
    assert np.max(np.abs(split.total_damping - e.damping)) < 1e-12 * scale
    assert np.max(np.abs(split.total_friction - e.friction)) < 1e-12 * scale
    # every type dissipates here, and none creates energy
    assert np.all(split.damping[-1] > 0) and np.all(split.friction[-1] > 0)
    assert np.all(np.diff(split.damping, axis=0) >= -1e-15)
    d, f = split.of("baffle")
    assert d[-1] == split.damping[-1, 3] and f[-1] == split.friction[-1, 3]
    ds = split.to_dataset()
    assert ds.damping.dims == ("time", "contact") and list(ds.contact.values) == list(CONTACT_TYPES)
    # asked for, the split changes nothing of the motion (the same bits)
    plain = run_case(case)
    assert np.array_equal(plain.signals.force, res.signals.force)
    assert np.array_equal(plain.signals.velocity, res.signals.velocity)


def test_the_contacts_of_a_resting_column_carry_its_weight():
    """Two spheres stacked on the floor of a still container: the pair carries the top sphere's
    weight, the floor both; the coordination number counts them."""
    case = still_case([[0.0, R, 0.0], [0.0, 3 * R, 0.0]], [[0.0, 0.0, 0.0]] * 2, duration=0.2, eps=0.3, gravity=G)
    sim = Simulation(case, recorders=[ContactsRecorder(every=100)])
    rec = sim.run().outputs["contacts"]
    assert rec.time.tolist() == pytest.approx([0.1, 0.2])
    c = rec.contacts[-1]
    mg = sphere_mass() * G
    pair = c.kind == CONTACT_TYPES.index("sphere")
    floor = c.kind == CONTACT_TYPES.index("floor")
    assert c.ends[pair].tolist() == [[0, 1]] and c.ends[floor].tolist() == [[0, -1 - sim.walls.floor]]
    assert pair.sum() + floor.sum() == c.kind.size  # no other wall is touched
    assert c.normal_force[pair][0] == pytest.approx(mg, rel=1e-3)
    assert c.normal_force[floor][0] == pytest.approx(2 * mg, rel=1e-3)
    assert rec.coordination_number().tolist() == [1.0, 1.0]      # 2 P / N = 2 x 1 / 2
    assert coordination_number(c, walls=True) == 1.5             # the floor counts for the bottom sphere
    assert coordination_number(c, walls=True, rattlers=False) == 2.0   # the top sphere has one contact
    assert c.wall_names[-1 - c.ends[floor][0, 1]] == "floor"


def test_the_contacts_channel_needs_a_python_recorder():
    r = ContactsRecorder(every=1)
    r.every = 0
    with pytest.raises(ValueError, match="contacts channel with every = 0"):
        check_recorders([r])
    with pytest.raises(ValueError, match="every = 0"):
        ContactsRecorder(every=0)
