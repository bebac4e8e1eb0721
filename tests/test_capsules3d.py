"""3D capsules (spherocylinders, saxum.ModelBuilder.add_capsule in 3D): mass properties, bad
input, the contacts with polyhedra, spheres and capsules, drawing, determinism."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

import saxum as sx
from saxum.geometry3d import rotation_matrix
from saxum.model import drawn_polyhedra

LENGTH, RADIUS = 0.4, 0.05


def _finalize(builder, friction=0.5):
    law = sx.ContactLaw(friction=friction)
    for group in builder.groups:
        builder.set_law("block", group, law)
    return builder.finalize()


def _contacts(model):
    detector = sx.Simulation(model, dt=1e-3, detection=sx.DetectionSettings(alert=0.02)
                             ).detector
    c = detector.contacts_at(model.body_q0)
    assert np.all(np.diff(c.key[: c.count]) > 0)  # the warm start's merge needs this
    assert np.linalg.det(c.frame[: c.count]) == pytest.approx(np.ones(c.count), abs=1e-12)
    found = {}
    for k in range(c.count):
        found.setdefault((model.body_name[c.candidate[k]], model.body_name[c.antagonist[k]]),
                         []).append(k)
    return c, found


def test_spherocylinder_properties_match_an_integral_over_slices():
    # independent check of the parallel-axis formulas: the solid as discs of radius a(z) along
    # its axis, V = int pi a^2, J_axis = int pi a^4 / 2, J_across = int pi a^2 (a^2 / 4 + z^2)
    # dz, by adaptive quadrature (its error estimate ~1e-15 here): 1e-10 relative
    def a2(z):
        beyond = max(abs(z) - 0.5 * LENGTH, 0.0)
        return RADIUS**2 - beyond**2

    span = 0.5 * LENGTH + RADIUS
    cuts = [-0.5 * LENGTH, 0.5 * LENGTH]
    volume = quad(lambda z: math.pi * a2(z), -span, span, points=cuts)[0]
    axial = quad(lambda z: 0.5 * math.pi * a2(z) ** 2, -span, span, points=cuts)[0]
    across = quad(lambda z: math.pi * a2(z) * (0.25 * a2(z) + z * z), -span, span,
                  points=cuts)[0]
    assert sx.spherocylinder_properties(LENGTH, RADIUS) == pytest.approx(
        (volume, axial, across), rel=1e-10)
    b = sx.ModelBuilder(dim=3)
    axis = np.array([1.0, -2.0, 2.0]) / 3.0
    c = b.add_capsule((1.0, 2.0, 3.0), LENGTH, RADIUS, axis=2.0 * axis, density=2000.0)
    m = _finalize(b)
    assert m.body_mass[c] == pytest.approx(2000.0 * volume, rel=1e-10)
    assert m.body_inertia[c] == pytest.approx(2000.0 * np.array([across, across, axial]),
                                              rel=1e-10)
    assert m.body_q0[c, :3] == pytest.approx([1.0, 2.0, 3.0], abs=1e-14)
    assert rotation_matrix(m.body_q0[c, 3:])[:, 2] == pytest.approx(axis, abs=1e-14)
    assert m.body_shape[c] == sx.Shape.CAPSULE and m.has_round
    assert m.body_size[c] == pytest.approx(volume ** (1.0 / 3.0), rel=1e-10)


@pytest.mark.parametrize(("length", "radius", "what"), [
    (0.0, 0.1, "length"), (-1.0, 0.1, "length"), (0.3, 0.0, "radius"), (0.3, -0.1, "radius")])
def test_bad_capsule_sizes_are_named_in_3d(length, radius, what):
    with pytest.raises(sx.InputError, match=rf"rod: the capsule's {what} must be a finite "
                       r"length > 0 \[m\]"):
        sx.ModelBuilder(dim=3).add_capsule((0.0, 0.0, 0.0), length, radius, density=2000.0,
                                           name="rod")


@pytest.mark.parametrize("density", [0.0, -2000.0])
def test_bad_capsule_density_and_axis_are_named(density):
    with pytest.raises(sx.InputError, match="rod: density must be a finite number > 0"):
        sx.ModelBuilder(dim=3).add_capsule((0.0, 0.0, 0.0), 0.3, 0.1, density=density,
                                           name="rod")
    with pytest.raises(sx.InputError, match="rod: the capsule's axis must be a non-zero"):
        sx.ModelBuilder(dim=3).add_capsule((0.0, 0.0, 0.0), 0.3, 0.1, axis=(0.0, 0.0, 0.0),
                                           density=2000.0, name="rod")


def test_capsule_contacts_with_polyhedra_spheres_and_capsules():
    # distances by Pythagoras; capsules 0.4 long with ends of radius 0.05, alert 0.02
    b = sx.ModelBuilder(dim=3)
    b.add_block([(x, y, z) for x in (-0.1, 0.1) for y in (-0.1, 0.1) for z in (-0.2, 0.0)],
                kind=sx.BodyKind.FIXED, group="ground", name="post")
    # a pyramid whose apex points up at (1, 0, 0)
    b.add_block([(1.1, 0.1, -0.2), (0.9, 0.1, -0.2), (1.1, -0.1, -0.2), (0.9, -0.1, -0.2),
                 (1.0, 0.0, 0.0)], kind=sx.BodyKind.FIXED, group="ground", name="apex")
    # along x across the post's top, 0.003 above it: the post's two top edges along y
    b.add_capsule((0.05, 0.0, 0.053), LENGTH, RADIUS, density=2000.0, name="rod")
    # along y over the rod, 0.004 above its side: the two segments pass each other
    b.add_capsule((0.0, 0.0, 0.157), LENGTH, RADIUS, axis=(0.0, 1.0, 0.0), density=2000.0,
                  name="cross")
    # a brick lying across `cross`, 0.003 above it: its bottom edges along x pass over it
    b.add_block([(x, y, z) for x in (-0.3, 0.3) for y in (-0.05, 0.05) for z in (0.21, 0.3)],
                density=2000.0, name="brick")
    # along y on the apex, 0.006 above it; a sphere against its end, 0.005 apart
    b.add_capsule((1.0, 0.05, 0.056), LENGTH, RADIUS, axis=(0.0, 1.0, 0.0), density=2000.0,
                  name="on apex")
    b.add_sphere((1.0, 0.05 + 0.2 + 0.105, 0.056), 0.05, density=2000.0, name="ball")
    c, found = _contacts(_finalize(b))
    expected = {("rod", "post"): [(-0.1, 0.0, 0.003), (0.1, 0.0, 0.003)],
                ("rod", "cross"): [(0.0, 0.0, 0.103)],
                ("cross", "brick"): [(0.0, -0.05, 0.207), (0.0, 0.05, 0.207)],
                ("on apex", "apex"): [(1.0, 0.0, 0.006)]}
    gaps = {("rod", "post"): 0.003, ("rod", "cross"): 0.004, ("cross", "brick"): 0.003,
            ("on apex", "apex"): 0.006}
    normals = {("rod", "post"): 1.0, ("rod", "cross"): -1.0, ("cross", "brick"): -1.0,
               ("on apex", "apex"): 1.0}
    # crossing at right angles: the ellipse g < a of area pi 2 sqrt(r r) (a - g); an edge
    # against the side: no area (as an edge against an edge of two polyhedra)
    assert c.area[found[("rod", "cross")]] == pytest.approx(
        [math.pi * 2.0 * RADIUS * (0.02 - 0.004)], rel=1e-12)
    assert c.area[found[("rod", "post")]] == pytest.approx([0.0, 0.0], abs=1e-15)
    for pair, points in expected.items():
        rows = found.pop(pair)
        assert c.point[rows] == pytest.approx(np.array(points), abs=1e-12), pair
        assert c.gap[rows] == pytest.approx(gaps[pair], abs=1e-12), pair
        assert c.frame[rows, 1] == pytest.approx(np.array([[0.0, 0.0, normals[pair]]]
                                                          * len(rows)), abs=1e-12), pair
    (k,) = found.pop(("on apex", "ball"))
    assert c.gap[k] == pytest.approx(0.005, abs=1e-12)
    assert c.frame[k, 1] == pytest.approx([0.0, -1.0, 0.0], abs=1e-12)
    assert not found  # nothing else within the alert distance


def test_parallel_capsules_touch_at_two_points():
    b = sx.ModelBuilder(dim=3)
    b.add_capsule((0.0, 0.0, 0.0), LENGTH, RADIUS, axis=(1.0, 1.0, 0.0),
                  kind=sx.BodyKind.FIXED, group="ground", name="low")
    shift = 0.1 * np.array([1.0, 1.0, 0.0]) / math.sqrt(2.0)
    b.add_capsule(shift + (0.0, 0.0, 0.103), LENGTH, RADIUS, axis=(1.0, 1.0, 0.0),
                  density=2000.0, name="high")
    c, _ = _contacts(_finalize(b))
    assert c.count == 2
    assert c.gap[: c.count] == pytest.approx([0.003, 0.003], abs=1e-12)
    along = c.point[: c.count] @ (np.array([1.0, 1.0, 0.0]) / math.sqrt(2.0))
    assert sorted(along) == pytest.approx([-0.1, 0.2], abs=1e-12)


def test_capsule_is_drawn_inside_itself():
    b = sx.ModelBuilder(dim=3)
    b.add_plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0), name="plane")
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    rod = b.add_capsule((0.0, 0.0, 0.3), LENGTH, RADIUS, axis=axis, density=2000.0)
    m = _finalize(b)
    g = drawn_polyhedra({k: getattr(m, k) for k in (
        "body_vertex_start", "vertex_local", "body_face_start", "face_vertex_start",
        "face_vertex", "body_round_radius", "body_shape")})
    local = g["vertex_local"][g["body_vertex_start"][rod]:g["body_vertex_start"][rod + 1]]
    # every drawn vertex lies on the capsule's surface (at r from its segment), the poles at
    # its tips, and its faces close it outwards
    along = np.clip(local[:, 2], -0.5 * LENGTH, 0.5 * LENGTH)
    distance = np.hypot(np.hypot(local[:, 0], local[:, 1]), local[:, 2] - along)
    assert distance == pytest.approx(np.full(len(local), RADIUS), abs=1e-12)
    assert np.ptp(local[:, 2]) == pytest.approx(LENGTH + 2.0 * RADIUS, abs=1e-12)
    first, last = g["body_face_start"][rod], g["body_face_start"][rod + 1]
    fvs, fv = g["face_vertex_start"], g["face_vertex"]
    volume = 0.0
    for f in range(first, last):
        ring = g["vertex_local"][fv[fvs[f]:fvs[f + 1]]]
        for k in range(1, len(ring) - 1):
            volume += np.linalg.det(np.array([ring[0], ring[k], ring[k + 1]])) / 6.0
    assert 0.9 * sx.spherocylinder_properties(LENGTH, RADIUS)[0] < volume


def test_polyhedra_alone_never_call_the_round_kernel(monkeypatch):
    # numba compiles a kernel on its first call: never called, never compiled
    def refuse(*args):
        raise AssertionError("round_contacts called for a model of polyhedra")

    monkeypatch.setattr("saxum.detection.detector.round_contacts", refuse)
    b = sx.ModelBuilder(dim=3)
    b.add_plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0), name="plane")
    b.add_block([(x, y, z) for x in (0, 0.2) for y in (0, 0.2) for z in (0, 0.2)],
                density=2000.0)
    m = _finalize(b)
    assert not m.has_round
    sim = sx.Simulation(m, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 0.01)
    assert state.contacts.count == 4  # the cube's corners on the plane


def test_3d_capsules_are_refused_by_the_2d_only_writers(tmp_path):
    # block files and the LMGC90 exporter write a capsule as (centre, length, angle) / JONCx:
    # a 3D capsule must be refused by name, not written with a wrong axis
    from saxum.model import capsule_axis
    from saxum.structures.blockfile import write_blocks

    b = sx.ModelBuilder(dim=3)
    b.add_block([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-0.2, 0.0)],
                kind=sx.BodyKind.FIXED, name="ground")
    c = b.add_capsule((0.0, 0.0, RADIUS), LENGTH, RADIUS, density=2000.0, name="roller")
    m = _finalize(b)
    with pytest.raises(sx.InputError, match="roller"):
        write_blocks(tmp_path / "blocks.json", m)
    with pytest.raises(sx.InputError, match="CYLND"):
        sx.export_lmgc90(m, tmp_path / "DATBOX")
    with pytest.raises(sx.InputError, match="3D model"):
        capsule_axis(m, c)
