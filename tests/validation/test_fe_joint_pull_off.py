"""Pull-off of a cohesive joint on deformable (FE) blocks (mode I of saxum.laws COHESIVE with
saxum.bodies.fe), 2D and 3D, gravity off.

A deformable block stands bonded on a fixed ground; on it is bonded a heavy rigid block (or a
second deformable block and the rigid one on that), pulled up by a force that grows linearly
in time. The joint under test has the tensile strength f_t, the others 3 f_t, so it is the
one that breaks. The bilinear law (P.P. Camanho & C.G. Davila, NASA/TM-2002-211737, 2002)
carries a tensile stress k_n g up to f_t, then softens linearly to zero at the opening
2 G_I / f_t, so the joint's force peaks at f_t A and each of its points absorbs G_I times its
area until it is fully damaged (the closed forms of the bilinear law), A the sum of the
points' Contacts.area: the tributary lengths (3D: areas, a third of each boundary triangle at
the node) of the deformable block's boundary nodes (saxum.detection.fe_nodes, fe_nodes3d),
which sum to the joint's length (area).

Measured: the joint's force -sum R_n / h of each step, and the work of each point's force
over its gap (trapezoids, the point followed by its contact key from step to step: a point
whose key changed would start again cracked and lose its bond).
Tolerances: peak within 1 % of f_t A, the issue's. The law's peak is reached within one
step's opening increment (about 5e-4 of the onset opening f_t / k_n here, 1e-3 in 3D), and
the blocks' elastic vibration under a force that grows over 20 ms (their periods are below
0.4 ms) adds to the joint's force only a fraction of order (T_vib / T_rise)^2. Work within
2 % of G_I A (test_joint_pull_off's bound: damage is updated once per step from the
converged opening, which overshoots the softening branch by about one step's opening
increment over the softening length; measured 0.5 % in 3D).
"""

import numpy as np
import pytest
from test_joint_pull_off import G_I, box, cohesive

import saxum as sx
from saxum.fe import Elastic

F_T = 1.0e5  # [Pa]: test_joint_pull_off's law (k_n = 1e10 Pa/m, G_I = 10 J/m^2)
WIDTH = 0.2  # [m]: the joint's length (3D: the side of its square)
RATE = 1.0e6  # [N/m/s]: the pulling force's growth (3D: WIDTH times it), peak after 0.02 s
H = {2: 1.0e-5, 3: 2.0e-5}  # [s]; 3D: 1000 steps to the peak, the law's increment 1e-3


def _block(dim: int, y0: float, y1: float) -> list[tuple[float, ...]]:
    """The joint's square (3D: cube) column from height y0 to y1 [m]."""
    if dim == 2:
        return [(0.0, y0), (WIDTH, y0), (WIDTH, y1), (0.0, y1)]
    return box(0.0, WIDTH, 0.0, WIDTH, y0, y1)


@pytest.mark.parametrize(("dim", "under_test"), [(2, "deformable-rigid"),
                                                 (2, "deformable-deformable"),
                                                 (3, "deformable-deformable")])
def test_pull_off_peak_with_deformable_blocks(dim, under_test):
    h = H[dim]
    b = sx.ModelBuilder(gravity=(0.0,) * dim, dim=dim)
    material = Elastic(1.0e10, 0.2, 2000.0)
    size = 0.05 if dim == 2 else 0.1  # 3D: 3 x 3 nodes on the joint
    ground = ([(-0.2, -0.2), (0.4, -0.2), (0.4, 0.0), (-0.2, 0.0)] if dim == 2
              else box(-0.2, 0.4, -0.2, 0.4, -0.2, 0.0))
    b.add_block(ground, kind=sx.BodyKind.FIXED, group="ground")
    b.add_block(_block(dim, 0.0, 0.2), material=material, mesh_size=size, group="lower")
    y = 0.2
    if under_test == "deformable-deformable":
        b.add_block(_block(dim, 0.2, 0.4), material=material, mesh_size=size, group="upper")
        y = 0.4
    top = b.add_block(_block(dim, y, y + 2.0), density=1.0e4, group="top")
    pull = RATE if dim == 2 else RATE * WIDTH
    b.add_force([top], lambda t: (0.0,) * (dim - 1) + (pull * t,) + (0.0,) * (2 * dim - 3))
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
    sim = sx.Simulation(b.finalize(), dt=h)
    state = sim.initial_state()
    index = {name: k for k, name in enumerate(sim.model.group_names)}
    groups = sim.model.body_group

    def in_joint(c) -> np.ndarray:
        """The joint's points with an area (a rigid corner's contact has none: a dry one)."""
        n = c.count
        gc, ga = groups[c.candidate[:n]], groups[c.antagonist[:n]]
        i, j = index[tested[0]], index[tested[1]]
        return (((gc == i) & (ga == j)) | ((gc == j) & (ga == i))) & (c.area[:n] > 0.0)

    c = state.contacts
    joint = in_joint(c)
    area = c.area[: c.count][joint].sum()
    assert abs(area / WIDTH ** (dim - 1) - 1.0) < 1e-12  # the nodes' tributaries: round-off
    keys = c.key[: c.count][joint]
    force = []
    last = {}  # key: (force [N/m; 3D N], gap [m]) of the last step
    work = 0.0
    for _ in range(4000):
        sim.step(state)
        c = state.contacts
        joint = in_joint(c)
        point = -c.impulse[: c.count, 1][joint] / h
        force.append(point.sum())
        now = dict(zip(c.key[: c.count][joint].tolist(),
                       zip(point, c.gap[: c.count][joint], strict=True), strict=True))
        assert set(now) == set(keys.tolist())  # the bonded points keep their keys
        for k, (f, g) in now.items():
            f0, g0 = last.get(k, (f, g))
            work += 0.5 * (f + f0) * (g - g0)
        last = now
        if c.damage[: c.count][joint].min() >= 1.0:
            break
    else:
        raise AssertionError("the joint did not break")
    assert abs(max(force) / (F_T * area) - 1.0) < 0.01
    assert abs(work / (G_I * area) - 1.0) < 0.02
