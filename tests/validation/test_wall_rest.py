"""A running-bond brick wall at rest on a rigid ground stays at rest.

Closed form: a stack of rigid blocks on flat horizontal joints under gravity is in static
equilibrium with compressive joint forces (every brick's weight passes to the bricks below and
to the ground; no horizontal load, so no friction is mobilized). The exact solution is "nothing
moves"; what the simulation shows instead is numerical drift (solver tolerance, round-off).
Model: saxum.structures.running_bond_wall, 25 courses of 20 bricks (half bricks at the ends of
every other course, 512 bricks), 0.25 x 0.065 m, default law (gap-based Signorini-Coulomb,
mu = 0.6), default NLGS, dt = 1e-3 s, 1 s.
Tolerances: no brick moves by more than 0.1 mm (or turns by more than 1e-5 rad); the logged
largest interpenetration never exceeds 0.01 mm; no joint opens by 1 micrometre; NLGS converged
at every step, the first included (a cold start from zero impulses, which NLGS alone does not
end within its cap on the 2025-brick wall: it ends from the rest solution,
saxum.solver.equilibrium).
"""

import numpy as np

import saxum as sx
from saxum.structures import running_bond_wall


def test_running_bond_wall_stays_at_rest():
    model = running_bond_wall(courses=25, bricks=20)
    assert model.body_count == 1 + 25 * 20 + 12  # ground + bricks (odd courses: 21 pieces)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 1.0)
    assert len(sim.log) == 1000
    bricks = model.body_kind == sx.BodyKind.FREE
    moved = np.hypot(*(state.body_q[bricks, :2] - model.body_q0[bricks, :2]).T)
    assert moved.max() < 1e-4
    assert np.abs(state.body_q[bricks, 2] - model.body_q0[bricks, 2]).max() < 1e-5
    assert sim.log.max_interpenetration.max() < 1e-5
    assert np.all(sim.log.converged), (
        f"NLGS did not converge at steps {sim.log.non_converged()[:10]}")
    # no joint opened: every contact point's gap is within 1 micrometre of closed (which
    # contact points of this statically indeterminate assembly carry the load is not unique)
    gaps = state.contacts.gap[:state.contacts.count]
    assert gaps.size == sim.log.contacts[-1] and np.abs(gaps).max() < 1e-6
