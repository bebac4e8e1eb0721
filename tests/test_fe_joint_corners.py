"""The face a deformable block's node at the corner of a joint stands on
(saxum.detection.fe_nodes, fe_nodes3d: chosen by the node's outward direction among the faces
within the alert distance, keyed by the flat side): pressed into the joint it stays on the bed
face; slipping onto the next facet of that side it keeps its key; and a mortared pier with an
ordinary mortar stiffness keeps every bond under its load."""

import numpy as np
import pytest
from test_fe_bodies import PIER, PIER_3D

import saxum as sx
from saxum.contacts import Contacts
from saxum.detection.detector import detector_for
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder

STONE = Elastic(1.0e10, 0.2, 2000.0)


def _box(dim, x0, x1, y0, y1):
    """A block x0..x1 wide (3D: 0.2 m deep) from height y0 to y1 [m]."""
    if dim == 2:
        return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
    return [(x, z, y) for x in (x0, x1) for y in (y0, y1) for z in (0.0, 0.2)]


def _flush_pair(dim, lower):
    """On a fixed ground, a 0.4 m wide block (rigid or deformable: `lower`) and on it a
    deformable block of the same footprint, their sides flush: the upper block's bottom
    corners stand on the lower's top corners. Returns (model, the upper block's index)."""
    b = ModelBuilder(dim=dim)
    b.add_block(_box(dim, -1.0, 1.4, -0.2, 0.0), kind=BodyKind.FIXED, group="ground")
    if lower == "rigid":
        b.add_block(_box(dim, 0.0, 0.4, 0.0, 0.2), density=2000.0, group="block")
    else:
        b.add_block(_box(dim, 0.0, 0.4, 0.0, 0.2), material=STONE, mesh_size=0.1,
                    group="block")
    upper = b.add_block(_box(dim, 0.0, 0.4, 0.2, 0.4), material=STONE, mesh_size=0.1,
                        group="block")
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    return b.finalize(), upper


def _joint_contacts(model, upper, shift):
    """The contacts of the joint between the two blocks with the upper block's nodes moved by
    `shift` [m] (dim numbers; its boundary nodes, all that detection reads): (detector, key,
    normal, gap)."""
    detector = detector_for(model)
    fe = model.fe
    node_x = fe.node_x0.copy()
    block = fe.fe_index[upper]
    node_x[fe.boundary_node[fe.boundary_start[block]:fe.boundary_start[block + 1]]] += shift
    c = Contacts(model.dim)
    detector.detect(model.body_q0, c, node_x)
    n = c.count
    joint = (np.minimum(c.candidate[:n], c.antagonist[:n]) == upper - 1) & (
        np.maximum(c.candidate[:n], c.antagonist[:n]) == upper)
    return detector, c.key[:n][joint], c.frame[:n, 1][joint], c.gap[:n][joint]


@pytest.mark.parametrize("lower", ["rigid", "deformable"])
@pytest.mark.parametrize("dim", [2, 3])
def test_a_pressed_joint_keeps_its_corner_nodes_on_the_bed_face(dim, lower):
    """The upper block pressed into the lower by 10 times detection's tie (1e-3 of the alert
    distance, the closure sigma / k_n of a mortar joint of k_n = 1e10 Pa/m under 0.5 MPa
    here): every node of the joint, the corners' too, keeps its contact on the bed face,
    normal vertical and gap minus the depth (round-off of coordinates of ~1 m: 1e-12 m), and
    its key. The nearest face alone would put the corner nodes on the side face (gap 0)."""
    model, upper = _flush_pair(dim, lower)
    up = np.eye(dim)[-1]
    detector, key0, _, gap0 = _joint_contacts(model, upper, 0.0 * up)
    depth = 10.0 * 1e-3 * detector.alert
    _, key, normal, gap = _joint_contacts(model, upper, -depth * up)
    assert np.abs(gap0).max() < 1e-12
    assert len(key) == len(key0) == (5 if dim == 2 else 15)  # the joint's nodes
    assert np.array_equal(key, key0)
    assert np.abs(np.abs(normal @ up) - 1.0).max() < 1e-12
    assert np.abs(gap + depth).max() < 1e-12


@pytest.mark.parametrize("dim", [2, 3])
def test_a_node_that_slips_onto_the_next_facet_keeps_its_key(dim):
    """Two deformable blocks, the upper slipped along the joint by 1.5 facets (0.15 m on a 0.1
    m mesh) and pressed into it: each node of the joint still under the other block's face
    stands on another facet of the same flat side, and keeps the key it had (the key goes by
    the side, fe_nodes.flat_sides; by the facet, a node's joint law would start again,
    cracked)."""
    model, upper = _flush_pair(dim, "deformable")
    up = np.eye(dim)[-1]
    detector, key0, _, _ = _joint_contacts(model, upper, 0.0 * up)
    depth = 10.0 * 1e-3 * detector.alert
    # the lower block's nodes are the candidates (its index is the lower): moving the upper
    # block by -0.15 m moves each of them 0.15 m along the upper's bottom
    _, key, normal, _ = _joint_contacts(model, upper, -0.15 * np.eye(dim)[0] - depth * up)
    assert 0 < len(key) < len(key0)
    assert np.isin(key, key0).all()
    assert np.abs(np.abs(normal @ up) - 1.0).max() < 1e-12


MORTAR = """friction = 0.6
    kind = "cohesive"
    k_n = 1e10
    k_t = 4e9
    f_t = 1e5
    cohesion = 2e5
    g_i = 10.0
    g_ii = 50.0"""
"""A lime mortar joint: k_n = E_m / t = 1e8 Pa / 0.01 m (a 10 mm joint of a mortar of
E_m = 0.1 GPa), k_t = k_n / 2.5, f_t 0.1 MPa, c = 2 f_t."""


@pytest.mark.parametrize("text", [PIER, PIER_3D], ids=["2d", "3d"])
def test_a_mortared_pier_keeps_its_bonds_under_load(text):
    """The pier of two courses (3D: two blocks each) in stone (E = 10 GPa) on mortar joints of
    an ordinary stiffness (MORTAR) under twenty times its weight (the stress of a pier ~12 m
    tall: 0.12 MPa on the joint between the courses, a closure of 1.2e-5 m, twice
    detection's tie, 1e-3 of the alert distance) and a small sideways load (0.06 g at the
    end): no contact cracks, none is lost, and every contact keeps its key (a node at a
    joint's corner taken for a contact on the side face would start cracked: 16 of the 3D
    pier's 46 did before the rule of fe_nodes.prefer)."""
    from saxum.scenario import parse_scenario

    dim = 3 if "pier_3d" in text else 2
    gravity = [0.0] * (dim - 1) + [-20.0 * 9.81]
    text = (text.replace("friction = 0.6", MORTAR).replace("E = 1.0e7", "E = 1.0e10")
            .replace("[solver]", f"[loads]\ngravity = {gravity}\nload_factor_rate = 1.0\n\n"
                     "[solver]"))
    sim = parse_scenario(text).build_simulation()
    state = sim.initial_state()
    sim.step(state)
    first = state.contacts.copy()
    deepest = 0.0
    for _ in range(59):
        sim.step(state)
        c = state.contacts
        n = c.count
        assert np.array_equal(c.key[:n], first.key[: first.count])
        assert (c.damage[:n] < 1.0).all()
        between = c.antagonist[:n] != 0  # the joints between the courses, not on the ground
        deepest = min(deepest, c.gap[:n][between].min())
    assert deepest < -1.5e-3 * sim.detector.alert  # past the tie: the case in question
