"""The sticking start of steps with deformable blocks (saxum.solver.sticking) and the warm
start of node contacts by key."""

import numpy as np
import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation
from saxum.solver.nlgs import NLGS

BRICK = Elastic(1.0e10, 0.2, 2000.0, damping=(0.0, 1e-4))


def _stack(solver):
    """Ground, two deformable bricks in running bond on it, a rigid brick on top."""
    b = ModelBuilder()
    b.add_block([(-1, -0.2), (1.4, -0.2), (1.4, 0), (-1, 0)], kind=BodyKind.FIXED,
                group="ground")
    b.add_block([(0, 0), (0.4, 0), (0.4, 0.2), (0, 0.2)], material=BRICK, mesh_size=0.1,
                group="brick")
    b.add_block([(0.4, 0), (0.8, 0), (0.8, 0.2), (0.4, 0.2)], material=BRICK, mesh_size=0.1,
                group="brick")
    b.add_block([(0.2, 0.2), (0.6, 0.2), (0.6, 0.4), (0.2, 0.4)], density=2000.0,
                group="brick")
    return _simulation(b, solver)


def _simulation(b, solver):
    """The stack's simulation, mu = 0.6 in every joint, dt = 1 ms."""
    law = sx.ContactLaw(friction=0.6)
    b.set_law("brick", "ground", law)
    b.set_law("brick", "brick", law)
    return Simulation(b.finalize(), dt=1e-3, solver=solver)


def _stack_3d(solver):
    """_stack() extruded 0.2 m deep: ground slab, two deformable bricks, a rigid one on top."""
    def box(x0, x1, y0, y1):
        return [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (0.0, 0.2)]

    b = ModelBuilder(dim=3)
    b.add_block([(x, y, z) for x in (-1, 1.4) for y in (-0.4, 0.6) for z in (-0.2, 0)],
                kind=BodyKind.FIXED, group="ground")
    for x0, x1, y0, y1 in [(0, 0.4, 0, 0.2), (0.4, 0.8, 0, 0.2)]:
        b.add_block([(x, z, y) for x, y, z in box(x0, x1, y0, y1)], material=BRICK,
                    mesh_size=0.1, group="brick")
    b.add_block([(x, z, y) for x, y, z in box(0.2, 0.6, 0.2, 0.4)], density=2000.0,
                group="brick")
    return _simulation(b, solver)


def test_node_contacts_keep_their_keys():
    """Coincident nodes of the two bricks' head joint and of the rigid brick's bed sit on the
    common ends of collinear facets: every contact keeps its key (and its warm start) from
    step to step."""
    sim = _stack(NLGS())
    state = sim.initial_state()
    sim.step(state)
    for _ in range(4):
        previous = state.contacts.copy()
        sim.step(state)
        c = state.contacts
        assert c.count == previous.count
        assert np.array_equal(c.key[: c.count], previous.key[: previous.count])


@pytest.mark.parametrize(("stack", "steps"), [(_stack, 3), (_stack_3d, 1)], ids=["2d", "3d"])
def test_sticking_start_is_the_solution_nlgs_converges_to(stack, steps):
    """A step started from the sticking solution after one sweep gives the velocities that
    sweeps alone reach, within what the tolerance leaves: NLGS stops at a relative change of
    1e-11 per sweep, a distance of some 1e-9 of the impulses' effect for sweeps that shrink
    the error by 0.99 each; 1e-7 leaves a margin of 100 above it. (3D: the first step, whose
    start is taken; the second's is not, its statuses still changing, measured.)"""
    runs = []
    for rest_after in (0, 1):
        sim = stack(NLGS(tolerance=1e-11, max_iterations=200_000, rest_after=rest_after))
        state = sim.initial_state()
        for _ in range(steps):
            report = sim.step(state)
            assert report.converged
        runs.append((sim, state, report))
    (sim0, s0, r0), (sim1, s1, r1) = runs
    assert sim1.solver.rest_attempts == sim1.solver.rest_solutions == steps
    assert sim0.solver.rest_attempts == 0
    assert r1.iterations < r0.iterations / 10  # the start is (nearly) the solution
    scale = np.abs(s0.node_v - sim0.fe.v_free).max()
    assert np.abs(s1.node_v - s0.node_v).max() < 1e-7 * scale
    assert np.abs(s1.body_v[3] - s0.body_v[3]).max() < 1e-7 * np.abs(s0.body_v[3]).max() + \
        1e-7 * scale
