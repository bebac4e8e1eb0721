"""A slender 3D pier at rest on a rigid ground stays at rest, every step converged.

Closed form: as for the walls (test_wall_rest3d.py), rigid blocks on flat horizontal joints
under gravity are in static equilibrium with compressive joint forces; the exact solution is
that nothing moves. Model: saxum.structures.pier3d, 40 courses 0.065 m high of two blocks
0.125 x 0.25 m side by side, crossed from course to course (a pier 0.25 x 0.25 m, 2.6 m
high), density 1800 kg/m^3, mu = 0.6, default law and NLGS (tolerance 1e-6, 5000 sweeps),
dt = 1e-3 s, 1 s.

Why it is a test of the solver: as the 2D stack-bond tower (test_tower_rest.py), the pier bends
like a cantilever on which Gauss-Seidel gains little per sweep; NLGS alone (rest_after = 0)
hits its 5000-sweep cap on the cold start, then does 1873 sweeps per step on average and leaves
60 steps of the first second not converged, the blocks drifting by 1.8e-5 m (measured; about
100 s of computing against about 1 s with the rest solution). The rest solution
(saxum.solver.equilibrium, second-order cones) ends the cold start exactly and later steps
start from it. Tolerances: every step converged; no block moves by more than 1e-9 m (round-off);
fewer than 1 % of the steps need more than rest_after sweeps.
"""

import numpy as np

import saxum as sx
from saxum.structures import pier3d


def test_slender_pier_stands_one_second_with_every_step_converged():
    model = pier3d(width=0.25, depth=0.25, courses=40, course_height=0.065, density=1800.0)
    assert model.body_count == 1 + 40 * 2
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 1.0)
    assert len(sim.log) == 1000
    assert np.all(sim.log.converged), f"not converged at {sim.log.non_converged()[:10]}"
    blocks = model.body_kind == sx.BodyKind.FREE
    moved = np.linalg.norm(state.body_q[blocks, :3] - model.body_q0[blocks, :3], axis=1)
    assert moved.max() < 1e-9
    slow = np.count_nonzero(sim.log.iterations > sim.solver.rest_after)
    assert 1 <= slow < 10 and sim.solver.rest_solutions >= 1
