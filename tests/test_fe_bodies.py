"""Deformable blocks as a body kind (issue 14): model, detection of node contacts, the loop's
guards. Physics validation: tests/validation/test_fe_*.py."""

import numpy as np
import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation
from saxum.solver.hybrid import Hybrid

STONE = Elastic(1.0e9, 0.2, 2400.0)


def _block_on_ground(width=0.4, solver=None):
    b = ModelBuilder()
    b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=BodyKind.FIXED, group="ground")
    b.add_block([(0, 0), (width, 0), (width, 0.2), (0, 0.2)], material=STONE, mesh_size=0.05,
                group="block")
    law = sx.ContactLaw(friction=0.6)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    model = b.finalize()
    return model, Simulation(model, dt=1e-3, **({} if solver is None else {"solver": solver}))


def test_material_makes_a_deformable_body():
    model, _ = _block_on_ground()
    assert model.body_kind[1] == BodyKind.DEFORMABLE
    assert model.fe.count == 1 and model.fe.body[0] == 1
    assert not model.body_inv_mass[1].any()  # the rigid kernels leave its body row alone
    assert model.body_mass[1] == pytest.approx(2400.0 * 0.4 * 0.2, rel=1e-12)


def test_mesh_size_without_material_is_refused():
    b = ModelBuilder()
    with pytest.raises(sx.InputError, match="mesh_size"):
        b.add_block([(0, 0), (1, 0), (1, 1), (0, 1)], density=2000.0, mesh_size=0.1)


def test_deformable_3d_block_is_refused():
    b = ModelBuilder(dim=3)
    cube = [(x, y, z) for x in (0, 1) for y in (0, 1) for z in (0, 1)]
    with pytest.raises(sx.InputError, match="deformable"):
        b.add_block(cube, material=STONE)


def test_node_contacts_on_the_ground():
    """The bottom nodes touch the ground: one contact each, FE candidate side, keys increasing,
    areas summing to the block's width."""
    model, sim = _block_on_ground(width=0.4)
    state = sim.initial_state()
    sim.step(state)
    c = state.contacts
    n = c.count
    bottom = np.flatnonzero(np.abs(model.fe.node_x0[:, 1]) < 1e-12)
    assert n == len(bottom)
    assert (c.side_kind[:n, 0] == 1).all() and (c.side_kind[:n, 1] == 0).all()
    assert sorted(c.side_node[:n, 0, 0]) == sorted(bottom)
    assert (np.diff(c.key[:n]) > 0).all()
    assert c.area[:n].sum() == pytest.approx(0.4, rel=1e-12)
    assert (c.impulse[:n, 1] > 0.0).all()


def test_only_nlgs_solves_deformable_models():
    with pytest.raises(sx.InputError, match="NLGS"):
        _block_on_ground(solver=Hybrid())
