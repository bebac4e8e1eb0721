"""Dissipativity of the inelastic contact law in 3D: kinetic energy never increases over a step.

As in 2D (tests/validation/test_energy.py): without external forces one Moreau-Jean step
changes the kinetic energy by E+ - E- = R . U+ - 1/2 R . W R with W = H M^-1 H^T positive
semi-definite, and Signorini (R_n U_n+ = 0) with isotropic Coulomb friction (R_T . U_T+ <= 0)
gives E+ <= E- (J.J. Moreau 1988; M. Jean, CMAME 177, 1999; Acary & Brogliato 2008, sec.
10.1). In 3D the step also carries the free gyroscopic motion, which conserves the energy
exactly (saxum.bodies.rigid3d.gyroscopic_torques), so the same bound holds.
Property test (hypothesis): up to three free convex polyhedra (hulls of random points), with
random position, velocity and spin, thrown inside a closed box of fixed slabs; no gravity; law
SIGNORINI_COULOMB with random mu in [0, 1]; NLGS tolerance 1e-10.
Tolerance: E_k+1 <= E_k (1 + 1e-7) + 1e-12 E_0 at every step; the blocks stay in the box.
"""

import math

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial import ConvexHull

import saxum as sx
from saxum.bodies.rigid3d import kinetic_energy
from saxum.geometry3d import rotation_matrix
from saxum.structures.solid import box

CELL = 1.0  # blocks start in distinct cells of a 2 x 2 x 1 grid inside the box
BOX = 2.0 * CELL
WALL = 0.5
DT = 1e-3
STEPS = 500  # >= 3 m/s for 0.5 s: each block reaches a wall (<= 1.3 m away) or a block


def _polyhedron(seed, radius, centre):
    """Hull of 12 random points in a ball of `radius` around `centre` (kept inside it)."""
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(12, 3))
    p *= radius * rng.uniform(0.5, 1.0, size=(12, 1)) / np.linalg.norm(p, axis=1)[:, None]
    return p[ConvexHull(p).vertices] + centre


block_spec = st.tuples(
    st.integers(0, 10_000),                 # shape seed
    st.floats(0.15, 0.3),                   # radius [m]
    st.floats(3.0, 6.0),                    # speed [m/s]
    st.floats(-1.0, 1.0), st.floats(-1.0, 1.0), st.floats(-1.0, 1.0),  # direction
    st.floats(-10.0, 10.0), st.floats(-10.0, 10.0), st.floats(-10.0, 10.0),  # spin [rad/s]
    st.floats(500.0, 3000.0),               # density [kg/m^3]
)


def _build(blocks, mu):
    b = sx.ModelBuilder(dim=3, gravity=(0.0, 0.0, 0.0))
    lo, hi, top = -WALL, BOX + WALL, CELL
    for name, corners in {
        "floor": (lo, lo, lo, hi, hi, 0.0), "roof": (lo, lo, top, hi, hi, top + WALL),
        "west": (lo, lo, 0.0, 0.0, hi, top), "east": (BOX, lo, 0.0, hi, hi, top),
        "south": (0.0, lo, 0.0, BOX, 0.0, top), "north": (0.0, BOX, 0.0, BOX, hi, top),
    }.items():
        b.add_block(box(*corners), kind=sx.BodyKind.FIXED, group="wall", name=name)
    velocities = []
    for k, (seed, radius, speed, dx, dy, dz, wx, wy, wz, rho) in enumerate(blocks):
        centre = ((k % 2 + 0.5) * CELL, (k // 2 + 0.5) * CELL, 0.5 * CELL)
        b.add_block(_polyhedron(seed, radius, centre), density=rho, name=f"thrown {k}")
        d = np.array([dx, dy, dz]) + [1e-3, 0.0, 0.0]
        velocities.append(np.concatenate((speed * d / np.linalg.norm(d), [wx, wy, wz])))
    law = sx.ContactLaw(friction=mu, kind=sx.LawKind.SIGNORINI_COULOMB)
    b.set_law("block", "block", law)
    b.set_law("block", "wall", law)
    return b.finalize(), np.array(velocities)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(blocks=st.lists(block_spec, min_size=1, max_size=3), mu=st.floats(0.0, 1.0))
def test_kinetic_energy_never_increases_3d(blocks, mu):
    model, velocities = _build(blocks, mu)
    sim = sx.Simulation(model, dt=DT, solver=sx.NLGS(tolerance=1e-10, max_iterations=20000))
    state = sim.initial_state()  # distinct cells, radius <= 0.3 < CELL / 2: no overlap
    free = np.flatnonzero(model.body_kind == sx.BodyKind.FREE)
    for k, b in enumerate(free):
        state.body_v[b, :3] = velocities[k, :3]
        # the spin is given in the world frame
        state.body_v[b, 3:] = rotation_matrix(state.body_q[b, 3:]).T @ velocities[k, 3:]
    energy = [kinetic_energy(state.body_v, model.body_mass, model.body_inertia,
                                        model.body_inv_mass)]
    for _ in range(STEPS):
        sim.step(state)
    energy = np.concatenate([energy, sim.log.kinetic_energy])
    assert sim.log.active_contacts.max() > 0  # the blocks did hit something
    increase = np.diff(energy)
    allowed = 1e-7 * energy[:-1] + 1e-12 * energy[0]
    assert np.all(increase <= allowed), (
        f"kinetic energy rose by {increase.max():.3g} J at step {int(np.argmax(increase)) + 1}"
    )
    inside = (state.body_q[free, :3] > 0.0) & (state.body_q[free, :3] < [BOX, BOX, CELL])
    assert np.all(inside)
    assert math.isfinite(energy[-1])
