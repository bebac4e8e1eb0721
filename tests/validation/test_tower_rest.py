"""A slender stack-bond tower at rest on a rigid ground stays at rest, every step converged.

Closed form: as for the wall (test_wall_rest.py), rigid blocks on flat horizontal joints under
gravity are in static equilibrium with compressive joint forces; the exact solution is that
nothing moves. Model: saxum.structures.wall, stack bond, 40 courses of 2 bricks 0.25 x 0.065 m
(a tower 2.6 m high on a 0.5 m base; four bricks meet at every inner corner), density
1800 kg/m^3, mu = 0.6, default law and NLGS (tolerance 1e-6, 5000 sweeps), dt = 1e-3 s, 1 s.

Why it is a test of the solver: the tower's Delassus operator has eigenvalues down to 1.3e-6 of
the largest (it bends like a cantilever), on which a Gauss-Seidel sweep gains a factor
1 - 1.4e-5; NLGS alone hits its sweep cap from the cold start and then on about 30 steps per
second, the velocities that its errors leave opening and closing joints (benchmarks/
convergence.py). The rest solution (saxum.solver.equilibrium) ends the cold start exactly, and
the contacts at the corners where four bricks meet keep their normals (saxum.detection.
polygons: ties within the closed gap), so later steps start from the solution.
Tolerances: every step converged; no brick moves by more than 1e-9 m (round-off: NLGS alone
drifts by 1.6e-5 m); fewer than 1 % of the steps need more than rest_after sweeps.
"""

import numpy as np

import saxum as sx
from saxum.structures import wall


def test_stack_bond_tower_stands_one_second_with_every_step_converged():
    model = wall(courses=40, bricks=2, bond="stack")
    assert model.body_count == 1 + 40 * 2
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 1.0)
    assert len(sim.log) == 1000
    assert np.all(sim.log.converged), f"not converged at {sim.log.non_converged()[:10]}"
    bricks = model.body_kind == sx.BodyKind.FREE
    moved = np.hypot(*(state.body_q[bricks, :2] - model.body_q0[bricks, :2]).T)
    assert moved.max() < 1e-9
    slow = np.count_nonzero(sim.log.iterations > sim.solver.rest_after)
    assert 1 <= slow < 10 and sim.solver.rest_solutions >= 1
