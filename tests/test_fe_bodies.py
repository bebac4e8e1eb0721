"""Deformable blocks as a body kind (issue 14): model, detection of node contacts, the loop's
guards. Physics validation: tests/validation/test_fe_*.py."""

import textwrap

import numpy as np
import pytest

import saxum as sx
from saxum.fe import Elastic
from saxum.model import BodyKind, ModelBuilder
from saxum.simulation import Simulation
from saxum.solver.hybrid import Hybrid

STONE = Elastic(1.0e9, 0.2, 2400.0)


def _block_on_ground(width=0.4, solver=None):
    b = ModelBuilder()
    b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=BodyKind.FIXED, group="ground")
    b.add_block([(0, 0), (width, 0), (width, 0.2), (0, 0.2)], material=STONE, mesh_size=0.05,
                group="block")
    law = sx.ContactLaw(friction=0.6)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    model = b.finalize()
    return model, Simulation(model, dt=1e-3, **({} if solver is None else {"solver": solver}))


def test_material_makes_a_deformable_body():
    model, _ = _block_on_ground()
    assert model.body_kind[1] == BodyKind.DEFORMABLE
    assert model.fe.count == 1 and model.fe.body[0] == 1
    assert not model.body_inv_mass[1].any()  # the rigid kernels leave its body row alone
    assert model.body_mass[1] == pytest.approx(2400.0 * 0.4 * 0.2, rel=1e-12)


def test_mesh_size_without_material_is_refused():
    b = ModelBuilder()
    with pytest.raises(sx.InputError, match="mesh_size"):
        b.add_block([(0, 0), (1, 0), (1, 1), (0, 1)], density=2000.0, mesh_size=0.1)


def test_node_contacts_on_the_ground():
    """The bottom nodes touch the ground: one contact each, FE candidate side, keys increasing,
    areas summing to the block's width."""
    model, sim = _block_on_ground(width=0.4)
    state = sim.initial_state()
    sim.step(state)
    c = state.contacts
    n = c.count
    bottom = np.flatnonzero(np.abs(model.fe.node_x0[:, 1]) < 1e-12)
    assert n == len(bottom)
    assert (c.side_kind[:n, 0] == 1).all() and (c.side_kind[:n, 1] == 0).all()
    assert sorted(c.side_node[:n, 0, 0]) == sorted(bottom)
    assert (np.diff(c.key[:n]) > 0).all()
    assert c.area[:n].sum() == pytest.approx(0.4, rel=1e-12)
    assert (c.impulse[:n, 1] > 0.0).all()


def test_only_nlgs_solves_deformable_models():
    with pytest.raises(sx.InputError, match="NLGS"):
        _block_on_ground(solver=Hybrid())


def _stack(top_material):
    """A 0.4 x 0.2 deformable block on the ground and a 0.2 x 0.2 block centred on it,
    deformable or rigid (top_material None); settled for 0.3 s with damping."""
    b = ModelBuilder()
    b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=BodyKind.FIXED, group="ground")
    damped = Elastic(1.0e7, 0.2, 2000.0, damping=(0.0, 0.005))
    b.add_block([(0, 0), (0.4, 0), (0.4, 0.2), (0, 0.2)], material=damped, mesh_size=0.05,
                group="base")
    corners = [(0.1, 0.2), (0.3, 0.2), (0.3, 0.4), (0.1, 0.4)]
    if top_material is None:
        b.add_block(corners, density=2000.0, group="top")
    else:
        b.add_block(corners, material=top_material, mesh_size=0.05, group="top")
    law = sx.ContactLaw(friction=0.6)
    for g1, g2 in [("base", "ground"), ("base", "base"), ("top", "base"), ("top", "top"),
                   ("top", "ground")]:
        b.set_law(g1, g2, law)
    model = b.finalize()
    sim = Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 0.3)
    c = state.contacts
    n = c.count
    on_ground = c.antagonist[:n] == 0
    weight = 9.81 * 2000.0 * np.array([0.08, 0.04])
    upward = (c.impulse[:n, 0] * c.frame[:n, 0, 1] + c.impulse[:n, 1] * c.frame[:n, 1, 1]) / 1e-3
    on_top = np.where(c.candidate[:n] == 2, upward, -upward)  # the force on the top block
    return upward, on_top, on_ground, weight, state


@pytest.mark.parametrize("top", ["deformable", "rigid"])
def test_stack_carries_its_weight(top):
    """The ground carries both blocks' weight, the interface the top block's (the vertical
    component of the contact forces [N/m], within 1 %,
    once the damped vibration has settled); a rigid top block rests on the deformable one's
    nodes (node against its edge) and corners (its vertices against the facets)."""
    material = Elastic(1.0e7, 0.2, 2000.0, damping=(0.0, 0.005)) if top == "deformable" else None
    upward, on_top, on_ground, weight, state = _stack(material)
    assert upward[on_ground].sum() == pytest.approx(weight.sum(), rel=0.01)
    assert on_top[~on_ground].sum() == pytest.approx(weight[1], rel=0.01)
    if top == "rigid":
        assert np.abs(state.body_v[2]).max() < 1e-3


def test_scenario_materials_make_groups_deformable():
    """[[materials]] groups = [...] turns the free blocks of those groups into deformable
    ones with the material's density; a wrong group or a bad modulus names the table."""
    from saxum.scenario import parse_scenario

    text = textwrap.dedent("""\
        [structure]
        type = "semicircular_arch"
        radius = 1.0
        thickness = 0.15
        voussoirs = 5

        [[laws]]
        groups = ["*", "*"]
        friction = 0.6

        [[materials]]
        groups = ["voussoir"]
        E = 1.0e10
        nu = 0.2
        density = 2400.0
        mesh_size = 0.05

        [output]
        duration = 0.01
        """)
    model = parse_scenario(text).build_model()
    voussoirs = [b for b, name in enumerate(model.body_name) if "voussoir" in name]
    assert model.fe.count == len(voussoirs) == 5
    assert (model.body_kind[voussoirs] == BodyKind.DEFORMABLE).all()
    assert (model.body_density[voussoirs] == 2400.0).all()
    with pytest.raises(sx.InputError, match=r"materials\[0\].*'pier'"):
        parse_scenario(text.replace('groups = ["voussoir"]', 'groups = ["pier"]')).build_model()
    with pytest.raises(sx.InputError, match=r"line 13: materials\[0\]\.E"):
        parse_scenario(text.replace("E = 1.0e10", "E = -1.0")).build_model()
    with pytest.raises(sx.InputError, match=r"materials\[0\]: .*Poisson's ratio"):
        parse_scenario(text.replace("nu = 0.2", "nu = 0.7")).build_model()


PIER = textwrap.dedent("""\
    [structure]
    type = "pier"
    width = 0.3
    height = 0.6
    courses = 2

    [[laws]]
    groups = ["*", "*"]
    friction = 0.6

    [[materials]]
    groups = ["pier"]
    E = 1.0e7
    nu = 0.2
    density = 2000.0
    damping = [0.0, 0.002]
    mesh_size = 0.075

    [solver]
    dt = 1e-3

    [output]
    duration = 0.06
    interval = 0.01
    checkpoint_interval = 0.02
    """)


PIER_3D = PIER.replace('type = "pier"', 'type = "pier_3d"\ndepth = 0.3').replace(
    "height = 0.6", "course_height = 0.3").replace("mesh_size = 0.075", "mesh_size = 0.15")
"""The pier in 3D: two courses of two blocks each, split across x and across y in turn."""

PIER_3D_MORTAR = PIER_3D.replace("friction = 0.6", """friction = 0.6
    kind = "cohesive"
    k_n = 1e10
    k_t = 4e9
    f_t = 5e4
    cohesion = 1e5
    g_i = 5.0
    g_ii = 10.0""").replace("[solver]", "[loads]\nload_factor_rate = 25.0\n\n[solver]")
"""The 3D pier with mortar joints (saxum.laws COHESIVE, an ordinary lime mortar's stiffness:
tests/test_fe_joint_corners.py's MORTAR) under a sideways load growing at 25 g/s: its joints
start to crack between the middle checkpoint (0.04 s) and the end."""


def _check_rigid_motions(model, x, v, body_v):
    """The deformable blocks' rows of a results file's body_v [frames, blocks, dof] are, in
    every frame, the rigid motion nearest (mass-weighted) to the nodes' x, v [frames, N, d]:
    the centre of mass's velocity sum m_i v_i / sum m_i and the spin w solving I w = sum m_i
    r_i x v_i, I = sum m_i (|r_i|^2 1 - r_i r_i^T), written out here with numpy (tolerance:
    1e-12 of the largest speed, round-off of sums over ~100 nodes)."""
    from saxum.fe.blocks import FEBlocks

    d = model.dim
    blocks = FEBlocks.geometry(list(model.fe.meshes), list(model.fe.materials))
    scale = 1e-12 * max(np.abs(v).max(), 1e-3)
    starts = blocks.node_start
    for b, (start, end) in enumerate(zip(starts[:-1], starts[1:], strict=True)):
        m = blocks.node_mass[start:end]
        c = np.einsum("i,fid->fd", m, x[:, start:end]) / m.sum()
        assert np.abs(body_v[:, b, :d] - np.einsum("i,fid->fd", m, v[:, start:end]) / m.sum()
                      ).max() < scale
        r = np.zeros((len(x), end - start, 3))
        u = np.zeros_like(r)
        r[..., :d] = x[:, start:end] - c[:, None]
        u[..., :d] = v[:, start:end]
        moment = np.einsum("i,fik->fk", m, np.cross(r, u))
        inertia = (np.einsum("i,fi->f", m, (r * r).sum(-1))[:, None, None] * np.eye(3)
                   - np.einsum("i,fik,fil->fkl", m, r, r))
        spin = (moment[:, 2] / inertia[:, 2, 2])[:, None] if d == 2 else np.linalg.solve(
            inertia, moment[..., None])[..., 0]
        assert np.abs(body_v[:, b, d:] - spin).max() * 0.3 < scale  # 0.3 m: a block's size


@pytest.mark.parametrize("text", [PIER, PIER_3D, PIER_3D_MORTAR],
                         ids=["2d", "3d", "3d-mortar"])
def test_results_and_restart_are_bit_identical(tmp_path, text):
    """A run of two deformable courses on the ground writes the nodes and the contact sides in
    its frames and checkpoints; restarting from a checkpoint in the middle gives the last
    frame bit for bit (two runs on this machine, as tests/results_check.py compares); with
    mortar joints, the joints' damage too, which grows after the checkpoint."""
    from saxum.results import Results
    from saxum.runner import run_scenario
    from saxum.scenario import parse_scenario

    scenario = parse_scenario(text)
    path = tmp_path / "pier.h5"
    run_scenario(scenario, path, quiet=True)
    model = scenario.build_model()
    with Results(path) as r:
        assert r.node_x.shape == (r.frame_count, model.fe.node_count, model.dim)
        last = {"node_x": r.node_x[-1], "node_v": r.node_v[-1], "body_q": r.body_q[-1]}
        contacts = r.contacts(r.frame_count - 1)
        assert (contacts["side_kind"][:, 0] == 1).all()  # every contact has a node candidate
        saved = r.checkpoint(int(np.flatnonzero(r.checkpoint_steps == 40)[0]))
        assert (contacts["damage"].max() > 0.0) == ("cohesive" in text)
        x, v, body_v = r.node_x[:], r.node_v[:], r.body_v[:, model.fe.body]
    _check_rigid_motions(model, x, v, body_v)
    sim = scenario.build_simulation()
    state = sim.restore(saved)
    for _ in range(20):
        sim.step(state)
    for name, value in last.items():
        assert np.array_equal(getattr(state, name), value), name
    c = state.contacts
    for name, value in contacts.items():
        if name != "force":
            assert np.array_equal(getattr(c, name)[: c.count], value), name


def test_info_finds_the_collapse_of_a_deformable_block(tmp_path, capsys):
    """`saxum info` of a run in which a deformable block (0.4 x 0.2 m, mu = 0.5) slides under a
    horizontal acceleration of 1 g: it counts the block as deformable, finds the collapse
    (saxum.collapse.find_collapse: the block slides on, 0.5 g net, ~0.2 m in 0.3 s) and
    names the sliding base as the mechanism, from the nodes' velocities in the file. The run
    says on stderr which stages it leaves out for deformable blocks, and why."""
    from saxum.cli import main

    text = (PIER.replace("width = 0.3", "width = 0.4").replace("height = 0.6", "height = 0.2")
            .replace("courses = 2", "courses = 1").replace("friction = 0.6", "friction = 0.5")
            .replace("E = 1.0e7", "E = 1.0e9").replace("mesh_size = 0.075", "mesh_size = 0.1")
            .replace("[solver]", "[loads]\nhorizontal_acceleration = 9.81\n\n[solver]")
            .replace("duration = 0.06", "duration = 0.3"))
    scenario = tmp_path / "slide.toml"
    scenario.write_text(text)
    assert main(["run", str(scenario), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "saxum: note: deformable blocks: the rest solution, load following and the " in err
    assert "(they are written for rigid blocks)" in err
    assert main(["info", str(tmp_path / "slide.h5")]) == 0
    out = capsys.readouterr().out
    assert "(0 free, 1 deformable)" in out
    assert "collapse at t = " in out and "'pier c1' moved by more than" in out
    assert "sliding joint between ground and pier c1" in out


@pytest.mark.parametrize("text", [PIER, PIER_3D, PIER_3D_MORTAR],
                         ids=["2d", "3d", "3d-mortar"])
def test_stresses_in_results_and_paraview_export(tmp_path, text):
    """Results.stresses gives the cell stresses of the stored nodes (the same as the run's
    own blocks give for them), the piers are compressed on average, and the ParaView export
    writes the triangle (3D: tetrahedron) meshes with them as a third part. (The stored nodes,
    not those of a second run: a run with checkpoints restarts its solver's memory at each, as
    a resumed run does, so that its sticking starts can differ from an uninterrupted run's.)"""
    import meshio

    from saxum.results import Results
    from saxum.runner import run_scenario
    from saxum.scenario import parse_scenario
    from saxum.vtk import export_vtk

    scenario = parse_scenario(text)
    path = tmp_path / "pier.h5"
    run_scenario(scenario, path, quiet=True)
    sim = scenario.build_simulation()
    dim = sim.model.dim
    with Results(path) as r:
        stored = r.stresses(-1)
        blocks = sim.fe.blocks
        x = r.node_x[-1]
        own = blocks.stresses(x, *blocks.frames(x))[0]
        assert np.array_equal(stored["stress"], own)
        # sigma_yy (3D: sigma_zz): compression under the weight
        assert stored["stress"][:, dim - 1].mean() < 0.0
        assert (stored["compression"] >= 0.0).all() and (stored["tension"] >= 0.0).all()
        pvd = export_vtk(r, tmp_path / "vtk", frames=[-1])
        k = r.frame_count - 1
    assert f"elements_{k:06d}.vtu" in pvd.read_text()
    mesh = meshio.read(tmp_path / "vtk" / "pier" / f"elements_{k:06d}.vtu")
    cell = "triangle" if dim == 2 else "tetra"
    assert mesh.cells_dict[cell].shape == (len(stored["stress"]), dim + 1)
    assert np.allclose(mesh.cell_data["compression"][0], stored["compression"], rtol=1e-12,
                       atol=0.0)


def test_plot_draws_the_meshes_by_compression(tmp_path):
    """saxum plot of a run with deformable blocks fills their triangles by the largest
    compression, with a colour bar in MPa."""
    from matplotlib.collections import PolyCollection

    from saxum.plot import plot_frame
    from saxum.results import Results
    from saxum.runner import run_scenario
    from saxum.scenario import parse_scenario

    path = tmp_path / "pier.h5"
    run_scenario(parse_scenario(PIER), path, quiet=True)
    with Results(path) as r:
        fig = plot_frame(r, -1, tmp_path / "pier.png")
        cells = len(r.model["fe_cell_node"])
    ax = fig.axes[0]
    meshes = [c for c in ax.collections
              if isinstance(c, PolyCollection) and len(c.get_paths()) == cells]
    assert len(meshes) == 1
    assert any(a.get_ylabel() == "largest compression [MPa]" for a in fig.axes[1:])
    assert (tmp_path / "pier.png").stat().st_size > 0


@pytest.mark.parametrize("size, match", [(5.0, "larger than the block"),
                                         (0.001, "nodes, more than max_nodes")])
def test_bad_mesh_size_names_the_block(size, match):
    b = ModelBuilder()
    b.add_block([(0, 0), (0.4, 0), (0.4, 0.2), (0, 0.2)], material=STONE, mesh_size=size,
                name="keystone")
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    with pytest.raises(sx.InputError, match=f"keystone: mesh size.*{match}"):
        b.finalize()


def test_a_fixed_block_cannot_be_deformable():
    with pytest.raises(sx.InputError, match="only a free block can be deformable"):
        ModelBuilder().add_block([(0, 0), (1, 0), (1, 1), (0, 1)], material=STONE,
                                 kind=BodyKind.FIXED)


BRICK_2D = [(0, 0), (0.4, 0), (0.4, 0.2), (0, 0.2)]
BRICK_3D = [(x, y, z) for x in (0, 0.4) for y in (0, 0.2) for z in (0, 0.2)]


@pytest.mark.parametrize("dim", [2, 3])
def test_a_given_mesh_is_the_blocks_mesh(dim):
    """add_block(mesh=...) takes a user's mesh of the block: the mesher's own mesh given back
    makes the same deformable body as its mesh size; a hand-made one (two triangles, six
    tetrahedra around a diagonal) is taken as it is."""
    from saxum.fe import Mesh, mesh_polygon, mesh_polyhedron

    vertices = BRICK_2D if dim == 2 else BRICK_3D
    if dim == 2:
        made = mesh_polygon(vertices, 0.1)
        hand = Mesh.from_cells(vertices, [(0, 1, 2), (0, 2, 3)])
    else:
        faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2),
                 (1, 3, 7, 5)]
        made = mesh_polyhedron(np.array(vertices, dtype=float), faces, 0.1)
        hand = Mesh.from_cells(vertices, [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7),
                                          (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7)])
    models = []
    for kwargs in ({"mesh_size": 0.1}, {"mesh": made}, {"mesh": hand}):
        b = ModelBuilder(dim=dim)
        b.add_block(vertices, material=STONE, **kwargs)
        b.set_law("block", "block", sx.ContactLaw(friction=0.6))
        models.append(b.finalize())
    assert np.array_equal(models[0].fe.node_x0, models[1].fe.node_x0)
    assert np.array_equal(models[0].fe.facet_node, models[1].fe.facet_node)
    assert np.array_equal(models[2].fe.node_x0, np.array(vertices, dtype=float))
    assert models[2].body_mass[0] == pytest.approx(models[0].body_mass[0], rel=1e-12)


@pytest.mark.parametrize("cells, nodes, match", [
    ([(0, 1, 2)], BRICK_2D[:3], "does not fill the block"),
    ([(0, 1, 2), (0, 2, 3)], [(0, 0), (0.5, 0), (0.4, 0.2), (0, 0.2)], "lie outside the block"),
])
def test_a_given_mesh_that_is_not_the_blocks_is_refused(cells, nodes, match):
    from saxum.fe import Mesh

    b = ModelBuilder()
    b.add_block(BRICK_2D, material=STONE, mesh=Mesh.from_cells(nodes, cells), name="keystone")
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    with pytest.raises(sx.InputError, match=f"keystone: .*{match}"):
        b.finalize()
    with pytest.raises(sx.InputError, match="keystone: give mesh_size or mesh, not both"):
        ModelBuilder().add_block(BRICK_2D, material=STONE, mesh_size=0.1, name="keystone",
                                 mesh=Mesh.from_cells(nodes, cells))
    with pytest.raises(sx.InputError, match="mesh_size and mesh are for deformable blocks"):
        ModelBuilder().add_block(BRICK_2D, density=2000.0, mesh=Mesh.from_cells(nodes, cells))
