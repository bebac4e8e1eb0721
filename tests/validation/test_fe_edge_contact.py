"""Rigid edges and corners on deformable blocks in 3D (issue 14; saxum.detection.fe_nodes3d):
where a rigid block touches a deformable one by an edge or a corner, there is no node of the
mesh on the rigid block's faces, and no corner, or only one, on the block's triangles.

Leaning slab (statics of a rigid body, three forces): a rigid slab (length L, thickness T,
leaning by phi from the vertical) stands with its lowest edge across the top face of an
elastic block, between two rows of the mesh's nodes and longer than the block is deep (its
corners beyond the block), its top edge against a frictionless fixed wall. Moments about the
base edge give the wall's push H = W (L sin phi - T cos phi) / (2 L cos phi), and the base
carries W vertically and H horizontally (W the slab's weight). Without the edge-edge contacts
(saxum before them) the slab found no contact on the block and fell through its face: 12 mm
in the first 50 ms, free fall; the wedge below, too.
Tolerance 1 %: the block's compression (~1e-6 of its height) moves the geometry by far less;
measured within 2e-6.

Driven indenters: a rigid pyramid pressed apex down into the block's top face between its
nodes, and a rigid wedge pressed edge down across it (longer than the block is deep), at
0.01 m/s for 60 ms, 0.5 mm into the block once they touch: neither passes through the face
(the end-of-step gap stays above -2.5e-5 m, 5 % of the push, the theta = 1/2 scheme's drift
at h v = 1e-5 m per step) and the block pushes back."""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

BLOCK = Elastic(1.0e8, 0.2, 2000.0, damping=(0.0, 0.002))
PHI, L, T, RHO, G = math.radians(20.0), 0.5, 0.05, 2000.0, 9.81
DEPTH = 0.6  # the slab's and the wedge's length across the 0.4 m deep block [m]


def _box(x0, x1, y0, y1, z0, z1):
    return [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]


def _builder():
    """Fixed ground, a 0.4 x 0.4 x 0.2 m elastic block on it, nodes every 0.1 m."""
    b = ModelBuilder(dim=3)
    b.add_block(_box(-1, 1, -1, 1, -0.2, 0), kind=BodyKind.FIXED, group="ground")
    b.add_block(_box(0, 0.4, 0, 0.4, 0, 0.2), material=BLOCK, mesh_size=0.1, group="block")
    return b


def _laws(b, groups):
    law = sx.ContactLaw(friction=0.6)
    for g1, g2 in groups:
        b.set_law(g1, g2, law)


def _forces_on(state, body, other, h):
    """Sum of the contact forces [N] (world axes) on `body` from `other`, and the gaps [m]."""
    c = state.contacts
    n = c.count
    force = np.einsum("ck,ckd->cd", c.impulse[:n], c.frame[:n]) / h
    on = c.candidate[:n] == body
    pair = (on & (c.antagonist[:n] == other)) | ((c.candidate[:n] == other)
                                                 & (c.antagonist[:n] == body))
    sign = np.where(on, 1.0, -1.0)[:, None]  # the antagonist pushes the candidate along +R
    return (sign * force)[pair].sum(axis=0), c.gap[:n][pair], pair


def test_leaning_slab_stands_on_its_edge_across_a_deformable_block():
    a = np.array([math.sin(PHI), 0.0, math.cos(PHI)])  # along the slab
    across = np.array([math.cos(PHI), 0.0, -math.sin(PHI)])  # through it, toward the wall
    base = np.array([0.27, 0.0, 0.2])  # its lowest edge: between the node rows x = 0.2, 0.3
    p0 = base - T * across
    wall_x = (base + L * a)[0]
    b = _builder()
    b.add_block(_box(wall_x, wall_x + 0.1, -0.2, 0.6, 0.0, 0.8), kind=BodyKind.FIXED,
                group="wall")
    slab = b.add_block([tuple(p0 + u * across + w * a + (0.0, y, 0.0)) for u in (0.0, T)
                        for w in (0.0, L) for y in (-0.1, DEPTH - 0.1)], density=RHO,
                       group="slab")
    _laws(b, [("block", "ground"), ("block", "block"), ("slab", "block"), ("slab", "slab"),
              ("slab", "ground"), ("wall", "block")])
    b.set_law("slab", "wall", sx.ContactLaw(friction=0.0))
    model = b.finalize()
    h = 1e-3
    sim = Simulation(model, dt=h, theta=1.0)
    state = sim.initial_state()
    for _ in range(100):
        report = sim.step(state)
    assert report.converged
    weight = RHO * T * L * DEPTH * G
    push = weight * (L * math.sin(PHI) - T * math.cos(PHI)) / (2.0 * L * math.cos(PHI))
    force, gaps, pair = _forces_on(state, slab, 1, h)
    assert force[2] == pytest.approx(weight, rel=0.01)
    assert force[0] == pytest.approx(push, rel=0.01)
    wall, _, _ = _forces_on(state, slab, 2, h)
    assert -wall[0] == pytest.approx(push, rel=0.01)
    # the slab rests on edge crossings (two nodes a side), not on nodes or corners
    c = state.contacts
    assert (c.side_weight[: c.count][pair, 0, 1] > 0.0).all()
    assert gaps.min() > -1e-6  # (it fell through the face without these contacts)


@pytest.mark.parametrize("indenter", ["pyramid", "wedge"])
def test_driven_corner_and_edge_do_not_pass_through_a_deformable_face(indenter):
    b = _builder()
    if indenter == "pyramid":  # apex at (0.17, 0.23), between the nodes
        points = [(0.17, 0.23, 0.2001)] + [(0.17 + dx, 0.23 + dy, 0.3) for dx in (-0.08, 0.08)
                                            for dy in (-0.08, 0.08)]
    else:  # edge along y at x = 0.17, beyond the block on both sides
        points = [(x, y, z) for y in (-0.1, 0.5)
                  for x, z in [(0.17, 0.2001), (0.07, 0.3), (0.27, 0.3)]]
    speed = 0.01
    top = b.add_block(points, kind=BodyKind.DRIVEN, motion=lambda t: (0, 0, -speed, 0, 0, 0),
                      group="top")
    _laws(b, [("block", "ground"), ("block", "block"), ("top", "block"), ("top", "top"),
              ("top", "ground")])
    h = 1e-3
    sim = Simulation(b.finalize(), dt=h)
    state = sim.initial_state()
    for _ in range(60):
        sim.step(state)
    force, gaps, _ = _forces_on(state, top, 1, h)
    pushed = speed * 60 * h - 1e-4  # how far the indenter went past the face [m]
    assert gaps.size and gaps.min() > -0.05 * pushed
    assert force[2] > 0.0
