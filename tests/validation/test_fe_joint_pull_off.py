"""Pull-off of a cohesive joint on a deformable (FE) block (mode I of saxum.laws COHESIVE with
saxum.bodies.fe), 2D, gravity off.

A deformable block stands bonded on a fixed ground; on it is bonded a heavy rigid block (or a
second deformable block and the rigid one on that), pulled up by a force that grows linearly
in time. The joint under test has the tensile strength f_t, the others 3 f_t, so it is the
one that breaks. The bilinear law (P.P. Camanho & C.G. Davila, NASA/TM-2002-211737, 2002)
carries a tensile stress k_n g up to f_t, so the joint's force peaks at f_t A, A the sum of
its points' Contacts.area: the tributary lengths of the deformable block's boundary nodes
(saxum.detection.fe_nodes), which sum to the joint's length.

Tolerance: peak within 1 % of f_t A, the issue's. The law's peak is reached within one
step's opening increment (about 5e-4 of the onset opening f_t / k_n here), and the blocks'
elastic vibration under a force that grows over 20 ms (their periods are below 0.4 ms) adds
to the joint's force only a fraction of order (T_vib / T_rise)^2.
"""

import numpy as np
import pytest
from test_joint_pull_off import cohesive

import saxum as sx
from saxum.fe import Elastic

F_T = 1.0e5  # [Pa]: test_joint_pull_off's law (k_n = 1e10 Pa/m, G_I = 10 J/m^2)
WIDTH = 0.2  # [m]: the joint's length
RATE = 1.0e6  # [N/m/s]: the pulling force's growth, peak after 0.02 s
H = 1.0e-5  # [s]


def _square(y0: float, y1: float) -> list[tuple[float, float]]:
    return [(0.0, y0), (WIDTH, y0), (WIDTH, y1), (0.0, y1)]


@pytest.mark.parametrize("under_test", ["deformable-rigid", "deformable-deformable"])
def test_pull_off_peak_with_deformable_blocks(under_test):
    b = sx.ModelBuilder(gravity=(0.0, 0.0))
    material = Elastic(1.0e10, 0.2, 2000.0)
    b.add_block([(-0.2, -0.2), (0.4, -0.2), (0.4, 0.0), (-0.2, 0.0)], kind=sx.BodyKind.FIXED,
                group="ground")
    b.add_block(_square(0.0, 0.2), material=material, mesh_size=0.05, group="lower")
    y = 0.2
    if under_test == "deformable-deformable":
        b.add_block(_square(0.2, 0.4), material=material, mesh_size=0.05, group="upper")
        y = 0.4
    top = b.add_block(_square(y, y + 2.0), density=1.0e4, group="top")
    b.add_force([top], lambda t: (0.0, RATE * t, 0.0))
    strong, weak = cohesive(f_t=3 * F_T, cohesion=3 * F_T), cohesive()
    names = ["ground", "lower"] + (["upper"] if y > 0.3 else []) + ["top"]
    tested = ("lower", "top") if under_test == "deformable-rigid" else ("lower", "upper")
    neighbours = list(zip(names[:-1], names[1:], strict=True))
    for i, a in enumerate(names):
        for c in names[i:]:
            law = sx.ContactLaw(friction=0.6)  # pairs that do not touch
            if (a, c) in neighbours:
                law = weak if (a, c) == tested else strong
            b.set_law(a, c, law)
    sim = sx.Simulation(b.finalize(), dt=H)
    state = sim.initial_state()
    index = {name: k for k, name in enumerate(sim.model.group_names)}
    groups = sim.model.body_group

    def in_joint(c) -> np.ndarray:
        n = c.count
        gc, ga = groups[c.candidate[:n]], groups[c.antagonist[:n]]
        i, j = index[tested[0]], index[tested[1]]
        return ((gc == i) & (ga == j)) | ((gc == j) & (ga == i))

    c = state.contacts
    joint = in_joint(c)
    area = c.area[: c.count][joint].sum()
    assert abs(area / WIDTH - 1.0) < 1e-12  # the nodes' tributary lengths: round-off only
    force = []
    for _ in range(4000):
        sim.step(state)
        c = state.contacts
        joint = in_joint(c)
        force.append(-c.impulse[: c.count, 1][joint].sum() / H)
        if c.damage[: c.count][joint & (c.area[: c.count] > 0.0)].min() >= 1.0:
            break
    else:
        raise AssertionError("the joint did not break")
    assert abs(max(force) / (F_T * area) - 1.0) < 0.01
