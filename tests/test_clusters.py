"""Clusters (ModelBuilder.add_cluster): non-convex rigid blocks made of convex parts, each a
contactor of one body: detection over parts, contacts on bodies, files, LMGC90, drawings."""

import json

import numpy as np
import pytest

import saxum as sx
from saxum.detection import detector_for
from saxum.errors import InputError
from saxum.lmgc90 import export_lmgc90, import_lmgc90
from saxum.model import drawn_outlines
from saxum.results import Results, ResultsWriter
from saxum.scenario import load_scenario
from saxum.structures import extruded
from saxum.structures.blockfile import blocks_model, write_blocks


def _box(x0, x1, y0, y1, z0, z1):
    return [(x, y, z) for x in (x0, x1) for y in (y0, y1) for z in (z0, z1)]


def _rect(x0, x1, y0, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def _l_parts(dim, x=0.0):
    if dim == 3:
        return [_box(x, x + 1.0, 0, 0.3, 0, 0.2), _box(x, x + 0.2, 0, 0.3, 0.2, 1.2)]
    return [_rect(x, x + 1.0, 0, 0.2), _rect(x, x + 0.2, 0.2, 1.2)]


def _model(dim, clusters=2):
    b = sx.ModelBuilder(dim=dim)
    if dim == 3:
        b.add_block(_box(-2, 6, -2, 2, -0.2, 0), kind=sx.BodyKind.FIXED, group="ground",
                    name="ground")
    else:
        b.add_block(_rect(-2, 6, -0.2, 0), kind=sx.BodyKind.FIXED, group="ground",
                    name="ground")
    for k in range(clusters):
        b.add_cluster(_l_parts(dim, 1.5 * k), density=2000.0, name=f"L{k}")
    b.add_block(_rect(4.0, 4.5, 0, 0.5) if dim == 2 else _box(4.0, 4.5, 0, 0.3, 0, 0.5),
                density=2000.0, name="plain")
    law = sx.ContactLaw(friction=0.6)
    b.set_law("block", "ground", law)
    b.set_law("block", "block", law)
    return b.finalize()


@pytest.mark.parametrize("dim", [2, 3])
def test_contacts_join_bodies_and_never_two_parts_of_one_body(dim):
    model = _model(dim)
    assert model.clustered and len(model.contactor_body) == model.body_count + 2
    np.testing.assert_array_equal(model.contactor_body, [0, 1, 1, 2, 2, 3])
    contacts = detector_for(model).contacts_at(model.body_q0)
    n = contacts.count
    # each L's foot on the ground (2 corners in 2D, 4 in 3D), the plain block's too; the
    # parts of one L share a face and make no contact
    assert n == 3 * (2 if dim == 2 else 4)
    assert set(contacts.antagonist[:n]) | set(contacts.candidate[:n]) == {0, 1, 2, 3}
    assert np.all(contacts.candidate[:n] != contacts.antagonist[:n])


def test_a_model_without_clusters_keeps_one_contactor_per_body():
    b = sx.ModelBuilder(dim=3)
    b.add_block(_box(0, 1, 0, 1, 0, 1), density=2000.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    model = b.finalize()
    assert not model.clustered
    assert model.contactor_vertex_start is model.body_vertex_start


@pytest.mark.parametrize("dim", [2, 3])
def test_block_file_round_trip(tmp_path, dim):
    model = _model(dim)
    write_blocks(tmp_path / "blocks.json", model)
    rows = json.loads((tmp_path / "blocks.json").read_text())["blocks"]
    assert [len(r.get("parts", [])) for r in rows] == [0, 2, 2, 0]
    back = blocks_model(tmp_path / "blocks.json")
    np.testing.assert_allclose(back.body_mass, model.body_mass, rtol=1e-14)
    np.testing.assert_allclose(back.body_q0[:, :dim], model.body_q0[:, :dim], atol=1e-14)
    np.testing.assert_array_equal(back.contactor_body, model.contactor_body)
    with pytest.raises(InputError, match="'L0' is a cluster"):
        write_blocks(tmp_path / "blocks.csv", model)


@pytest.mark.parametrize("dim", [2, 3])
def test_lmgc90_round_trip(tmp_path, dim):
    """A cluster goes out as one body with a POLYG (POLYR) per part and comes back whole."""
    model = _model(dim)
    export_lmgc90(model, tmp_path / "DATBOX", precision="full", alert=0.01)
    text = (tmp_path / "DATBOX" / "BODIES.DAT").read_text()
    tact = "POLYG" if dim == 2 else "POLYR"
    assert text.count(f" {tact}      2  color") == 2  # the second part of each L
    imported = import_lmgc90(tmp_path / "DATBOX")
    back = imported.model()
    imported.write_scenario(tmp_path / "model.toml")  # its blocks file holds the parts
    scenario = load_scenario(tmp_path / "model.toml").build_model()
    for other in (back, scenario):
        np.testing.assert_array_equal(other.contactor_body, model.contactor_body)
        np.testing.assert_allclose(other.body_mass, model.body_mass, rtol=1e-12)
    for b in range(model.body_count):
        for p, q in zip(model.part_vertices(b), back.part_vertices(b), strict=True):
            apart = np.linalg.norm(p[:, None, :] - q[None, :, :], axis=2)
            assert apart.min(axis=1).max() < 1e-12


def test_lmgc90_cluster_of_mixed_contactors_is_refused(tmp_path):
    model = _model(3, clusters=1)
    export_lmgc90(model, tmp_path / "DATBOX", precision="full", alert=0.01)
    path = tmp_path / "DATBOX" / "BODIES.DAT"
    text = path.read_text()
    second = text.index(" POLYR      2  color")
    line = text[:text.index("$bdyty", text.rindex("$bdyty", 0, second))].count("\n") + 2
    path.write_text(text[:second] + text[second:].replace("color  BLO01", "color  OTHER", 1))
    with pytest.raises(InputError, match=f"BODIES.DAT line {line}: RBDY3 2 is a cluster of 2 "
                                         "contactors with contactors of colours BLO01, OTHER"):
        import_lmgc90(tmp_path / "DATBOX")


def test_bad_clusters_are_named():
    b = sx.ModelBuilder()
    with pytest.raises(InputError, match="arch part 1: polygon is not strictly convex"):
        b.add_cluster([_rect(0, 1, 0, 1), [(1, 0), (2, 0), (1.5, 0.2), (2, 1), (1, 1)]],
                      density=2000.0, name="arch")
    with pytest.raises(InputError, match="stone: parts must be a list of convex parts"):
        b.add_cluster([], density=2000.0, name="stone")
    b.add_cluster(_l_parts(2), density=2000.0, name="L", group="stones")
    with pytest.raises(InputError, match="the cluster 'L'"):
        b.set_material("stones", sx.Elastic(E=1e9, nu=0.2, density=2000.0))
    b.set_law("stones", "stones", sx.ContactLaw(friction=0.6))
    b.add_field_load(sx.FloodLoad(level=0.5))
    with pytest.raises(InputError, match="1 block.* are clusters .e.g. 'L'., which a flood"):
        b.finalize()


def test_2d_drawing_joins_the_parts_of_a_cluster(tmp_path):
    """The ring that draws a 2D cluster has the area of its parts (shoelace), in plots and
    results files alike."""
    model = _model(2, clusters=1)
    start, local = drawn_outlines(model.body_vertex_start, model.vertex_local, None,
                                  contactor_start=model.contactor_vertex_start)
    ring = local[start[1]:start[2]]
    x, y = ring.T
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    assert area == pytest.approx(0.2 + 0.2, rel=1e-12)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    path = tmp_path / "run.h5"
    with ResultsWriter(path, model, dt=1e-3, theta=0.5) as out:
        out.write_frame(state)
    with Results(path) as res:
        np.testing.assert_array_equal(res.model["contactor_vertex_start"],
                                      model.contactor_vertex_start)
        assert res.body_size[1] == pytest.approx(model.body_size[1], rel=1e-15)


def test_extruded_2d_cluster_is_a_3d_cluster():
    """A 2D cluster given a depth (saxum.structures.extruded) keeps its parts: mass per metre
    of depth times the depth, the same contactors."""
    model = _model(2, clusters=1)
    solid = extruded(model, 0.5)
    np.testing.assert_array_equal(solid.contactor_body, model.contactor_body)
    assert solid.body_mass[1] == pytest.approx(0.5 * model.body_mass[1], rel=1e-12)
