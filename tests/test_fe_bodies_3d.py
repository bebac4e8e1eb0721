"""Deformable blocks in 3D models (issue 14): model, node-face detection, stacks of rigid and
deformable blocks (results, restart and ParaView export of a 3D pier:
tests/test_fe_bodies.py). Physics validation: tests/validation/test_fe_*.py."""

import numpy as np
import pytest
from test_fe_bodies import PIER_3D

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation

DAMPED = Elastic(1.0e7, 0.2, 2000.0, damping=(0.0, 0.005))


def _box(x0, x1, y0, y1, z0, z1):
    return [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]


def _builder():
    b = ModelBuilder(dim=3)
    b.add_block(_box(-1, 1, -1, 1, -0.2, 0), kind=BodyKind.FIXED, group="ground")
    return b


def test_material_makes_a_deformable_3d_body():
    b = _builder()
    b.add_block(_box(0, 0.4, 0, 0.2, 0, 0.2), material=DAMPED, mesh_size=0.1, group="block")
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = b.finalize()
    assert model.body_kind[1] == BodyKind.DEFORMABLE
    assert model.fe.node_x0.shape == (5 * 3 * 3, 3)
    assert model.fe.facet_node.shape[1] == 3
    # every boundary triangle's area is shared by its three nodes: the node sides sum to the
    # block's surface (2 (0.08 + 0.08 + 0.04) m^2) as vectors of zero sum (a closed surface)
    assert np.linalg.norm(model.fe.node_side, axis=2).sum() == pytest.approx(0.4, rel=1e-12)
    assert np.abs(model.fe.node_side.sum(axis=(0, 1))).max() < 1e-15
    assert model.body_mass[1] == pytest.approx(2000.0 * 0.4 * 0.2 * 0.2, rel=1e-12)


def test_node_contacts_on_the_ground():
    """The bottom nodes touch the ground's top face: one contact each, FE candidate side,
    keys increasing, areas summing to the footprint, all loaded after a step."""
    b = _builder()
    b.add_block(_box(0, 0.4, 0, 0.2, 0, 0.2), material=DAMPED, mesh_size=0.1, group="block")
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = b.finalize()
    sim = Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.step(state)
    c = state.contacts
    n = c.count
    bottom = np.flatnonzero(np.abs(model.fe.node_x0[:, 2]) < 1e-12)
    assert n == len(bottom) == 15
    assert (c.side_kind[:n, 0] == 1).all() and (c.side_kind[:n, 1] == 0).all()
    assert sorted(c.side_node[:n, 0, 0]) == sorted(bottom)
    assert (np.diff(c.key[:n]) > 0).all()
    assert c.area[:n].sum() == pytest.approx(0.08, rel=1e-12)
    assert (c.impulse[:n, 1] > 0.0).all()
    assert np.abs(c.frame[:n, 1] - (0.0, 0.0, 1.0)).max() < 1e-15  # the ground's normal


@pytest.mark.parametrize("top", ["deformable", "rigid"])
def test_stack_carries_its_weight(top):
    """A 0.4 x 0.2 x 0.2 m deformable block on the ground and a 0.2 m cube centred on it,
    deformable (nodes against triangles) or rigid (its face against the nodes, its corners
    against the triangles), settled for 0.3 s with damping: the ground carries both weights
    and the interface the top block's (vertical components of the contact forces [N], 1 %)."""
    b = _builder()
    b.add_block(_box(0, 0.4, 0, 0.2, 0, 0.2), material=DAMPED, mesh_size=0.1, group="base")
    cube = _box(0.1, 0.3, 0, 0.2, 0.2, 0.4)
    if top == "rigid":
        b.add_block(cube, density=2000.0, group="top")
    else:
        b.add_block(cube, material=DAMPED, mesh_size=0.1, group="top")
    law = sx.ContactLaw(friction=0.6)
    for g1, g2 in [("base", "ground"), ("base", "base"), ("top", "base"), ("top", "top"),
                   ("top", "ground")]:
        b.set_law(g1, g2, law)
    sim = Simulation(b.finalize(), dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 0.3)
    c = state.contacts
    n = c.count
    upward = (c.impulse[:n] * c.frame[:n, :, 2]).sum(axis=1) / 1e-3
    on_ground = c.antagonist[:n] == 0
    on_top = np.where(c.candidate[:n] == 2, upward, -upward)
    weight = 9.81 * 2000.0 * np.array([0.016, 0.008])
    assert upward[on_ground].sum() == pytest.approx(weight.sum(), rel=0.01)
    assert on_top[~on_ground].sum() == pytest.approx(weight[1], rel=0.01)
    if top == "rigid":
        assert np.abs(state.body_v[2]).max() < 1e-3
        assert (c.side_kind[:n][c.candidate[:n] == 2, 0] == 0).any()  # its corners


def test_a_fixed_3d_block_cannot_be_deformable():
    with pytest.raises(sx.InputError, match="only a free block can be deformable"):
        ModelBuilder(dim=3).add_block(_box(0, 1, 0, 1, 0, 1), material=DAMPED,
                                      kind=BodyKind.FIXED)


def test_a_3d_material_with_a_thickness_is_refused():
    b = _builder()
    b.add_block(_box(0, 0.4, 0, 0.2, 0, 0.2), material=Elastic(1e7, 0.2, 2000.0,
                                                                 thickness=0.1),
                mesh_size=0.1, group="block")
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    with pytest.raises(sx.InputError, match="thickness"):
        b.finalize()


def test_plot_draws_the_meshes_by_compression(tmp_path):
    """saxum plot of a 3D run with deformable blocks draws their boundary triangles (in place
    of their polyhedra) filled by the largest compression, with a colour bar in MPa."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    from saxum.fe.mesh import boundary_facets
    from saxum.plot import plot_frame
    from saxum.results import Results
    from saxum.runner import run_scenario
    from saxum.scenario import parse_scenario

    path = tmp_path / "pier.h5"
    run_scenario(parse_scenario(PIER_3D.replace("duration = 0.06", "duration = 0.01")), path,
                 quiet=True)
    with Results(path) as r:
        fig = plot_frame(r, -1, tmp_path / "pier.png")
        facets = len(boundary_facets(r.model["fe_cell_node"], 3)[0])
    ax = fig.axes[0]
    meshes = [c for c in ax.collections
              if isinstance(c, Poly3DCollection) and len(c.get_paths()) == facets]
    assert len(meshes) == 1
    assert any(a.get_ylabel() == "largest compression [MPa]" for a in fig.axes[1:])


@pytest.mark.parametrize("dim", [2, 3])
def test_contact_rows_are_the_dense_delassus_and_warm_start(dim):
    """fe_contact_rows against numpy on the dense matrices: a contact whose candidate is a
    node of one block and whose antagonist a facet (weights w) of another, each block turned
    by its own R, gets W = H G H^T with G = R M~^-1 R^T (R node by node, M~^-1 in the block
    axes) and H = F B (B: +1 on the node, -w on the facet's nodes), and the warm start
    v = G H^T r (round-off: 1e-12 of the largest entry)."""
    from scipy.linalg import block_diag
    from scipy.spatial.transform import Rotation

    from saxum.bodies.fe import build_fe_bodies, fe_contact_rows
    from saxum.fe.blocks import FEBlocks
    from saxum.geometry3d import convex_polyhedron

    rng = np.random.default_rng(1)
    if dim == 2:
        shapes = [np.array([(0, 0), (0.4, 0), (0.4, 0.2), (0, 0.2)], dtype=float) + (0, y)
                  for y in (0.0, 0.2)]
        turns = [Rotation.from_euler("z", a).as_matrix()[:2, :2] for a in (0.7, -0.3)]
    else:
        shapes = [convex_polyhedron(_box(0, 0.4, 0, 0.2, z, z + 0.2)) for z in (0.0, 0.2)]
        turns = [Rotation.from_rotvec(r).as_matrix() for r in ([0.3, -0.5, 0.4],
                                                                [-0.2, 0.1, 0.6])]
    fe = build_fe_bodies([0, 1], shapes, [DAMPED, DAMPED], [0.1, 0.1], ["a", "b"], 2)
    blocks = FEBlocks.build(list(fe.meshes), list(fe.materials), 1e-3, 0.5)
    rotation = np.array(turns)
    frame = np.linalg.qr(rng.normal(size=(dim, dim)))[0][None]
    nodes = np.zeros((1, 2, dim), dtype=np.int32)
    weights = np.zeros((1, 2, dim))
    nodes[0, 0] = fe.boundary_node[0]
    weights[0, 0, 0] = 1.0
    nodes[0, 1] = fe.facet_node[fe.facet_start[1] + 3]
    weights[0, 1] = rng.dirichlet(np.ones(dim))
    impulse = rng.normal(size=(1, dim))
    n, dof = fe.node_count, 3 * (dim - 1)

    def call(kernel):
        h_cand, h_ant = np.zeros((1, dim, dof)), np.zeros((1, dim, dof))
        w, v = np.zeros((1, dim, dim)), np.zeros((n, dim))
        kernel(np.ones((1, 2), np.int8), nodes, weights, frame, impulse, 1,
               np.ones(1, bool), blocks.node_block, blocks.node_start, blocks.inv_start,
               blocks.inv, rotation, h_cand, h_ant, w, v)
        return w[0], v

    w, v = call(fe_contact_rows)
    g = []
    for k in range(2):
        size = dim * (blocks.node_start[k + 1] - blocks.node_start[k])
        inverse = blocks.inv[blocks.inv_start[k]:blocks.inv_start[k + 1]].reshape(size, size)
        turn = np.kron(np.eye(size // dim), turns[k])
        g.append(turn @ inverse @ turn.T)
    g = block_diag(*g)
    b = np.zeros((dim, dim * n))
    for side, sign in ((0, 1.0), (1, -1.0)):
        for p, s in zip(nodes[0, side], weights[0, side], strict=True):
            b[:, dim * p:dim * p + dim] += sign * s * np.eye(dim)
    h = frame[0] @ b
    assert np.abs(w - h @ g @ h.T).max() < 1e-12 * np.abs(w).max()
    assert np.abs(v.ravel() - g @ h.T @ impulse[0]).max() < 1e-12 * np.abs(v).max()
