"""A 3D running-bond brick wall with an L-shaped corner, at rest on a rigid ground, stays at rest.

Closed form: a stack of rigid blocks on flat horizontal joints under gravity is in static
equilibrium with compressive joint forces; the exact solution is "nothing moves", and what the
simulation shows instead is numerical drift (solver tolerance, round-off). Same check as the 2D
wall (tests/validation/test_wall_rest.py), required by issue 6: 0.1 mm over 1 s.
Model: saxum.structures.wall3d, 8 courses, a 1.5 m wall and a 0.75 m return wall interlocking
at the corner, bricks 0.25 x 0.12 x 0.065 m, default law (gap-based Signorini-Coulomb,
mu = 0.6), default NLGS, dt = 1e-3 s, 1 s.
Tolerances: no brick moves by more than 0.1 mm or turns by more than 1e-5 rad; the largest
interpenetration logged stays below 0.01 mm; no joint opens by 1 micrometre; face-to-face
contacts keep their 4 points, and every contact its identity at every step (what the warm start
needs; where bricks of the two walls touch at a single corner point, the narrow phase keeps one
normal: separations within the closed gap are ties); NLGS converged at every step, the cold
start from zero impulses included (the rest solution ends it: saxum.solver.equilibrium).
"""

import numpy as np

import saxum as sx
from saxum.geometry3d import quaternion_from_matrix, rotation_matrix
from saxum.structures import wall3d


def test_running_bond_wall_with_corner_stays_at_rest():
    model = wall3d(courses=8, length=1.5, return_length=0.75)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    face_points = []
    keys = []

    def count_face_points(state, report):
        """Contacts of body pairs touching by a face (3 or more points), and every key."""
        c = state.contacts
        keys.append(c.key[: c.count].copy())
        pairs = np.minimum(c.candidate[: c.count], c.antagonist[: c.count]) * model.body_count \
            + np.maximum(c.candidate[: c.count], c.antagonist[: c.count])
        per_pair = np.unique(pairs, return_counts=True)[1]
        face_points.append(int(per_pair[per_pair >= 3].sum()))

    sim.run(state, 1.0, callback=count_face_points)
    assert len(sim.log) == 1000
    bricks = model.body_kind == sx.BodyKind.FREE
    moved = np.linalg.norm(state.body_q[bricks, :3] - model.body_q0[bricks, :3], axis=1)
    assert moved.max() < 1e-4
    turned = [np.linalg.norm(quaternion_from_matrix(
        rotation_matrix(q0).T @ rotation_matrix(q))[1:]) * 2.0
        for q0, q in zip(model.body_q0[bricks, 3:], state.body_q[bricks, 3:], strict=True)]
    assert max(turned) < 1e-5
    assert sim.log.max_interpenetration.max() < 1e-5
    assert np.all(sim.log.converged), (
        f"NLGS did not converge at steps {sim.log.non_converged()[:10]}")
    assert np.all(np.array(face_points) == face_points[0])
    assert all(np.array_equal(k, keys[0]) for k in keys)
    assert face_points[0] % 4 == 0 and face_points[0] >= 0.95 * sim.log.contacts[-1]
    gaps = state.contacts.gap[: state.contacts.count]
    assert np.abs(gaps).max() < 1e-6
