"""ParaView export: the .pvd collection and the .vtu files read back with the results' values."""

import base64
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

import saxum as sx
from saxum.results import Results, ResultsWriter
from saxum.vtk import export_vtk

DT = 1e-3
BLOCK_FIELDS = {"displacement", "velocity", "rotation", "angular_velocity", "body_index",
                "body_kind"}
CONTACT_FIELDS = {"normal_force", "tangential_force", "force", "normal", "gap", "candidate",
                  "antagonist", "damage", "crush", "area"}


def _run(path, model, steps, every):
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state()
    with ResultsWriter(path, model, dt=DT, theta=0.5) as w:
        w.write_frame(state)
        for _ in range(steps):
            w.log_step(sim.step(state))
            if state.step % every == 0:
                w.write_frame(state)
        w.set_status(1)
    return path


def _pile():
    """Fixed ground (4 vertices), a free triangle and a free pentagon dropping onto it, and a
    driven square sliding along far away: three vertex counts and all three body kinds. The
    scene is tilted by 15 degrees (friction 0.6 holds the blocks), so that the contact frames
    are not the world axes."""
    c, s = np.cos(np.radians(15.0)), np.sin(np.radians(15.0))

    def tilt(points):
        return [(c * x - s * y, s * x + c * y) for x, y in points]

    b = sx.ModelBuilder()
    b.add_block(tilt([(-2, -0.2), (2, -0.2), (2, 0), (-2, 0)]), kind=sx.BodyKind.FIXED,
                name="ground")
    b.add_block(tilt([(-1, 0.001), (-0.4, 0.001), (-0.7, 0.5)]), density=2000.0)
    b.add_block(tilt([(0, 0.002), (0.5, 0.002), (0.6, 0.3), (0.25, 0.5), (-0.1, 0.3)]),
                density=2000.0)
    b.add_block([(5, 5), (6, 5), (6, 6), (5, 6)], kind=sx.BodyKind.DRIVEN,
                motion=lambda t: (1.0, 0.0, 0.5), name="driver")
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    return b.finalize()


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("vtk")
    path = _run(tmp / "pile.h5", _pile(), steps=60, every=20)
    res = Results(path)
    pvd = export_vtk(res, tmp / "out")
    yield res, pvd
    res.close()


def _datasets(pvd):
    root = ET.parse(pvd).getroot()
    assert root.tag == "VTKFile" and root.get("type") == "Collection"
    return root.find("Collection").findall("DataSet")


def _file(pvd, name, frame):
    return pvd.parent / "pile" / f"{name}_{frame:06d}.vtu"


def test_pvd_lists_both_parts_of_every_frame(exported):
    res, pvd = exported
    assert pvd == pvd.parent / "pile.pvd"
    sets = _datasets(pvd)
    assert len(sets) == 2 * res.frame_count == 8
    for i, ds in enumerate(sets):
        k, part = divmod(i, 2)
        assert float(ds.get("timestep")) == res.time[k]
        assert ds.get("part") == str(part)
        assert ds.get("name") == ("blocks", "contacts")[part]
        assert (pvd.parent / ds.get("file")).is_file()
        assert pvd.parent / ds.get("file") == _file(pvd, ds.get("name"), k)
    # The initial state has no contacts yet: an empty contacts file.
    assert len(res.contacts(0)["gap"]) == 0
    _assert_empty_vtu(_file(pvd, "contacts", 0), CONTACT_FIELDS)


def test_blocks_read_back(exported):
    res, pvd = exported
    n = len(res.body_name)
    q0 = res.model["body_q0"]
    for k in range(res.frame_count):
        mesh = meshio.read(_file(pvd, "blocks", k))
        assert {c.type for c in mesh.cells} == {"polygon"}
        assert sorted(c.data.shape[1] for c in mesh.cells) == [3, 4, 5]
        assert sum(len(c.data) for c in mesh.cells) == n
        assert mesh.points.shape == (res.model["vertex_local"].shape[0], 3)
        assert np.all(mesh.points[:, 2] == 0.0)
        data = {name: np.concatenate(v) for name, v in mesh.cell_data.items()}
        assert set(data) == BLOCK_FIELDS
        body = data["body_index"]
        assert sorted(body) == list(range(n))
        q, v = res.body_q[k][body], res.body_v[k][body]
        assert np.allclose(data["displacement"][:, :2], q[:, :2] - q0[body, :2], atol=1e-15)
        assert np.all(data["displacement"][:, 2] == 0.0)
        assert np.allclose(data["velocity"][:, :2], v[:, :2], atol=1e-15)
        assert np.allclose(data["rotation"], q[:, 2] - q0[body, 2], atol=1e-15)
        assert np.allclose(data["angular_velocity"], v[:, 2], atol=1e-15)
        assert np.array_equal(data["body_kind"], res.model["body_kind"][body])
        ground = np.flatnonzero(body == 0)[0]
        assert np.all(data["displacement"][ground] == 0.0)
    assert sorted(data["body_kind"]) == [0, 0, 1, 2]


@pytest.mark.parametrize(("body", "frame"), [(2, 2), (1, -1), (3, 3)])
def test_block_polygon_is_the_world_polygon(exported, body, frame):
    res, pvd = exported
    k = range(res.frame_count)[frame]
    mesh = meshio.read(_file(pvd, "blocks", k))
    (cell,) = [row for block, index in zip(mesh.cells, mesh.cell_data["body_index"], strict=True)
               for row in block.data[index == body]]
    assert np.allclose(mesh.points[cell, :2], res.vertices(body, k), rtol=0, atol=1e-12)


def test_contact_forces_are_world_vectors(exported):
    res, pvd = exported
    k = res.frame_count - 1
    c = res.contacts(k)
    assert len(c["gap"]) > 0
    mesh = meshio.read(_file(pvd, "contacts", k))
    assert [(cb.type, cb.data.shape) for cb in mesh.cells] == [("vertex", (len(c["gap"]), 1))]
    assert set(mesh.point_data) == CONTACT_FIELDS
    assert np.array_equal(mesh.points[:, :2], c["point"])
    r_t, r_n = c["impulse"][:, 0], c["impulse"][:, 1]
    t, nrm = c["frame"][:, 0], c["frame"][:, 1]
    expected = (r_t[:, None] * t + r_n[:, None] * nrm) / res.dt
    pd = mesh.point_data
    assert np.allclose(pd["force"][:, :2], expected, rtol=1e-14, atol=1e-9)
    assert np.all(pd["force"][:, 2] == 0.0)
    assert np.allclose(pd["normal_force"], r_n / res.dt, rtol=1e-14)
    assert np.allclose(pd["tangential_force"], r_t / res.dt, rtol=1e-14)
    assert np.array_equal(pd["normal"][:, :2], nrm)
    assert np.array_equal(pd["gap"], c["gap"])
    assert np.array_equal(pd["candidate"], c["candidate"])
    assert np.all(np.abs(nrm[:, 0]) > 0.2)  # tilted contact frames
    # The blocks rest on the inclined ground: the contact forces (normal and friction) add up to
    # their weight, straight up (they have settled).
    weight = 9.81 * res.model["body_mass"][[1, 2]].sum()
    assert np.allclose(pd["force"][:, :2].sum(axis=0), (0.0, weight), atol=1e-3 * weight)


def _assert_empty_vtu(path, fields):
    """meshio cannot read a mesh without points back, so the XML is checked directly: no points,
    no cells, every array present with a 0-byte payload (uncompressed header: UInt32 0)."""
    root = ET.parse(path).getroot()
    assert root.get("type") == "UnstructuredGrid" and root.get("compressor") is None
    piece = root.find("UnstructuredGrid/Piece")
    assert piece.get("NumberOfPoints") == "0" and piece.get("NumberOfCells") == "0"
    assert {a.get("Name") for a in piece.find("PointData")} == fields
    for array in piece.iter("DataArray"):
        assert base64.b64decode(array.text.strip()) == b"\0\0\0\0"


def test_frames_without_contacts(tmp_path):
    b = sx.ModelBuilder()
    b.add_block([(0, 0), (1, 0), (1, 1), (0, 1)], density=1000.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    path = _run(tmp_path / "flight.h5", b.finalize(), steps=20, every=10)
    pvd = export_vtk(path, tmp_path / "out")
    assert len(_datasets(pvd)) == 6
    with Results(path) as res:
        for k in range(res.frame_count):
            _assert_empty_vtu(pvd.parent / "flight" / f"contacts_{k:06d}.vtu", CONTACT_FIELDS)
            mesh = meshio.read(pvd.parent / "flight" / f"blocks_{k:06d}.vtu")
            drop = 0.5 * 9.81 * res.time[k] ** 2
            assert mesh.cell_data["displacement"][0][0, 1] == pytest.approx(-drop, abs=1e-12)


def test_frame_selection(exported, tmp_path):
    res, _ = exported
    pvd = export_vtk(res, tmp_path, frames=[0, -1])
    sets = _datasets(pvd)
    assert [ds.get("file") for ds in sets] == [
        "pile/blocks_000000.vtu", "pile/contacts_000000.vtu",
        "pile/blocks_000003.vtu", "pile/contacts_000003.vtu"]
    assert float(sets[-1].get("timestep")) == res.time[-1]
    assert sorted(p.name for p in (tmp_path / "pile").iterdir()) == sorted(
        Path(ds.get("file")).name for ds in sets)


def test_only_2d_and_3d_results(exported, tmp_path):
    """(3D export: tests/test_scenario3d.py.)"""
    res, _ = exported
    res.dim = 4
    try:
        with pytest.raises(sx.InputError, match="neither 2 nor 3"):
            export_vtk(res, tmp_path)
    finally:
        res.dim = 2


def test_vtk_reads_every_file(exported):
    """VTK's own reader (ParaView's) opens every file, the empty contacts file included."""
    vtk = pytest.importorskip("vtkmodules.vtkIOXML")
    res, pvd = exported
    for ds in _datasets(pvd):
        reader = vtk.vtkXMLUnstructuredGridReader()
        reader.SetFileName(str(pvd.parent / ds.get("file")))
        reader.Update()
        assert reader.GetErrorCode() == 0
        grid = reader.GetOutput()
        k = [float(t) for t in res.time].index(float(ds.get("timestep")))
        expected = len(res.body_name) if ds.get("name") == "blocks" else len(res.contacts(k)["gap"])
        assert grid.GetNumberOfCells() == expected
