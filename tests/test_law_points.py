"""Contact points for laws in stresses (saxum.laws.ContactLaw.points; detection in
saxum.detection.polygons and .polyhedra): extra points on face-to-face contacts whose areas
form a rule exact for the force and the moments of a linear stress, with the ends (corners)
kept, stable keys, and nothing changed for the default 2 points.

Tolerances: blocks of order 1 m; each area and each moment comes from a few differences of
world coordinates (round-off about 1e-16 m, more after turning the configuration) times
lengths of order 1 m, so 1e-12 [m, m^2, m^3 or m^4] leaves a margin of a thousand over the
round-off while any error of the rule (a wrong weight is off by a share of the joint, of
order 0.01 to 1) is ten orders of magnitude larger.
"""

import math

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import saxum as sx
from saxum.contacts import Contacts
from saxum.detection import DetectionSettings, detector_for
from saxum.errors import InputError
from saxum.structures.solid import box

TOL = 1e-12
ALERT = 0.01


def _turn2(points, angle):
    c, s = math.cos(angle), math.sin(angle)
    return [(c * x - s * y, s * x + c * y) for x, y in points]


def _box2(x0, y0, w, h, angle=0.0):
    return _turn2([(x0, y0), (x0 + w, y0), (x0 + w, y0 + h), (x0, y0 + h)], angle)


def _rotation(axis, angle):
    a = np.asarray(axis, dtype=float)
    a /= np.linalg.norm(a)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * k @ k


def _model(blocks, dim, points):
    b = sx.ModelBuilder(dim=dim)
    for k, vertices in enumerate(blocks):
        b.add_block(vertices, density=1000.0, name=f"block {k}")
    b.set_law("block", "block", sx.ContactLaw(friction=0.5, points=points))
    return b.finalize()


def _detect(blocks, dim, points):
    model = _model(blocks, dim, points)
    contacts = Contacts(dim)
    detector_for(model, DetectionSettings(alert=ALERT)).detect(model.body_q0, contacts)
    return contacts


def _rows(c):
    n = c.count
    return c.point[:n], c.area[:n], c.key[:n]


# -- 2D ---------------------------------------------------------------------------------------


def test_simpson_points_of_a_flush_joint():
    c = _detect([_box2(0, 0, 1.0, 0.5), _box2(0, 0.5, 1.0, 0.5)], 2, 3)
    point, area, key = _rows(c)
    assert c.count == 3
    x = point[:, 0]
    # ends keep their slots (0, 1), the middle is slot 2: b/6, b/6, 2b/3
    assert sorted(x) == pytest.approx([0.0, 0.5, 1.0], abs=TOL)
    assert area[np.argsort(x)] == pytest.approx([1 / 6, 2 / 3, 1 / 6], abs=TOL)
    assert np.all(np.diff(key) > 0)


def test_lobatto_panels_of_five_points():
    c = _detect([_box2(0, 0, 1.0, 0.5), _box2(0.2, 0.5, 1.0, 0.5)], 2, 5)  # 0.8 m overlap
    point, area, _ = _rows(c)
    order = np.argsort(point[:, 0])
    assert point[order, 0] == pytest.approx([0.2, 0.4, 0.6, 0.8, 1.0], abs=TOL)
    assert area[order] == pytest.approx(np.array([1, 4, 2, 4, 1]) * 0.8 / 12, abs=TOL)


def test_joint_open_beyond_alert_at_one_end_keeps_the_within_alert_length():
    # tilted by 3 alert over 1 m: a third of the joint is within alert, and the points there
    # share it (the default two points give it to the one end that is left)
    rise = 3.0 * ALERT
    upper = _turn2(_box2(0, 0, 1.0, 0.5), math.atan(rise))
    for points in (2, 3, 7):
        c = _detect([_box2(-0.2, -0.5, 1.4, 0.5), upper], 2, points)
        assert c.area[: c.count].sum() == pytest.approx(ALERT / rise, abs=TOL)
        assert np.all(c.gap[: c.count] <= ALERT)


@settings(max_examples=40, deadline=None)
@given(w0=st.floats(0.2, 2.0), w1=st.floats(0.2, 2.0), offset=st.floats(-0.9, 0.9),
       angle=st.floats(-math.pi, math.pi), lift=st.floats(0.0, 0.5 * ALERT),
       points=st.sampled_from([3, 5, 9]), slope=st.floats(-1e3, 1e3),
       mean=st.floats(-1e3, 1e3))
def test_property_2d_rule_is_exact_for_linear_stress(w0, w1, offset, angle, lift, points, slope,
                                                     mean):
    x1 = offset * w0
    lo, hi = max(0.0, x1), min(w0, x1 + w1)
    if hi - lo <= 1e-3:  # corner to corner: no joint (module doc of polygons)
        return
    blocks = [_turn2(_box2(0, 0, w0, 0.4), angle), _turn2(_box2(x1, 0.4 + lift, w1, 0.3), angle)]
    c = _detect(blocks, 2, points)
    point, area, _ = _rows(c)
    assert c.count == points
    x = np.array(_turn2(point, -angle))[:, 0]  # along the joint, in the blocks' frame
    sigma = mean + slope * (x - 0.5 * (lo + hi))  # a linear stress along the joint [Pa]
    exact_force = mean * (hi - lo)
    exact_moment = slope * (hi - lo) ** 3 / 12.0  # about the joint's middle
    scale = (abs(mean) + abs(slope)) * (1.0 + w0 + w1) ** 3
    assert area.sum() == pytest.approx(hi - lo, abs=TOL)
    assert np.sum(area * sigma) == pytest.approx(exact_force, abs=TOL * scale)
    assert np.sum(area * sigma * (x - 0.5 * (lo + hi))) == pytest.approx(exact_moment,
                                                                          abs=TOL * scale)
    # the ends are kept
    assert np.min(x) == pytest.approx(lo, abs=TOL) and np.max(x) == pytest.approx(hi, abs=TOL)


def test_three_points_give_the_rotational_stiffness_of_the_joint():
    # sum A_i x_i^2 about the middle: b^3/12 with Simpson, b^3/4 with the two ends
    b = 0.8
    blocks = [_box2(0, 0, b, 0.5), _box2(0, 0.5, b, 0.5)]
    for points, expected in ((2, b**3 / 4), (3, b**3 / 12)):
        point, area, _ = _rows(_detect(blocks, 2, points))
        assert np.sum(area * (point[:, 0] - b / 2) ** 2) == pytest.approx(expected, abs=TOL)


# -- 3D ---------------------------------------------------------------------------------------


def _polygon_moments(ring):
    """Area [m^2], first moments (x, y) [m^3] and second moments (xx, xy, yy) [m^4] about the
    origin of the polygon ring (x, y) [m], counterclockwise (Green's theorem)."""
    x, y = ring[:, 0], ring[:, 1]
    x1, y1 = np.roll(x, -1), np.roll(y, -1)
    cross = x * y1 - x1 * y
    return np.array([cross.sum() / 2, ((x + x1) * cross).sum() / 6,
                     ((y + y1) * cross).sum() / 6,
                     ((x * x + x * x1 + x1 * x1) * cross).sum() / 12,
                     ((x * y1 + 2 * x * y + 2 * x1 * y1 + x1 * y) * cross).sum() / 24,
                     ((y * y + y * y1 + y1 * y1) * cross).sum() / 12])


def _rule_moments(points, area):
    x, y = points[:, 0], points[:, 1]
    return np.array([area.sum(), (area * x).sum(), (area * y).sum(), (area * x * x).sum(),
                     (area * x * y).sum(), (area * y * y).sum()])


def _prism(ring, z0, z1):
    return np.array([(x, y, z) for z in (z0, z1) for x, y in ring])


def test_tensor_simpson_on_offset_bricks():
    c = _detect([box(0, 0, 0, 1, 1, 1), box(0.5, 0.25, 1, 1.5, 1.25, 2)], 3, 3)
    point, area, key = _rows(c)
    assert c.count == 9  # 4 corners, 4 edge midpoints, centre
    overlap = 0.5 * 0.75
    corner_axes = [int(np.isclose(x, (0.5, 1.0)).any()) + int(np.isclose(y, (0.25, 1.0)).any())
                   for x, y in point[:, :2]]
    share = {2: 1 / 36, 1: 4 / 36, 0: 16 / 36}  # corner, edge midpoint, centre
    assert area == pytest.approx([overlap * share[k] for k in corner_axes], abs=TOL)
    assert np.all(np.diff(key) > 0)
    assert point[-1] == pytest.approx([0.75, 0.625, 1.0], abs=TOL)


def test_triangle_rule_is_exact_to_degree_two():
    # a triangular prism standing inside the top face of a slab: the joint is the triangle
    ring = np.array([(0.1, 0.1), (0.9, 0.2), (0.3, 0.8)])
    c = _detect([box(0, 0, -0.5, 1, 1, 0), _prism(ring, 0.0, 0.5)], 3, 3)
    assert c.count == 7
    point, area, _ = _rows(c)
    assert _rule_moments(point, area) == pytest.approx(_polygon_moments(ring), abs=TOL)


def test_octagon_fan_is_exact_for_linear_stress():
    # two unit squares, one turned by 45 degrees, both moved off the origin: the joint is a
    # regular octagon; the fan rule is exact for the area and the first moments only
    turn = _rotation((0, 0, 1), math.pi / 4)
    shift = np.array([0.3, -0.7, 0.0])
    lower = box(-0.5, -0.5, -1, 0.5, 0.5, 0) + shift
    upper = box(-0.5, -0.5, 0, 0.5, 0.5, 1) @ turn.T + shift
    c = _detect([lower, upper], 3, 3)
    assert c.count == 17
    point, area, _ = _rows(c)
    octagon = 2.0 * (math.sqrt(2.0) - 1.0)
    exact = [octagon, octagon * shift[0], octagon * shift[1]]
    assert _rule_moments(point, area)[:3] == pytest.approx(exact, abs=TOL)


@settings(max_examples=40, deadline=None)
@given(centre=st.tuples(st.floats(0.35, 0.65), st.floats(0.35, 0.65)),
       size=st.tuples(st.floats(0.1, 0.3), st.floats(0.1, 0.3)), spin=st.floats(-3.2, 3.2),
       jitter=st.lists(st.floats(-0.04, 0.04), min_size=8, max_size=8),
       axis=st.tuples(st.floats(-1, 1), st.floats(-1, 1), st.floats(0.1, 1)),
       angle=st.floats(-math.pi, math.pi), lift=st.floats(0.0, 0.5 * ALERT))
def test_property_quadrilateral_rule_is_exact_to_degree_two(centre, size, spin, jitter, axis,
                                                            angle, lift):
    # a prism on any convex quadrilateral (a turned rectangle with its corners moved a
    # little) standing on a slab, the whole turned in space: the joint is the quadrilateral,
    # and the rule on its bilinear map integrates every quadratic stress exactly
    c0, s0 = math.cos(spin), math.sin(spin)
    local = np.array([(-1, -1), (1, -1), (1, 1), (-1, 1)]) * size
    ring = (local @ np.array([[c0, s0], [-s0, c0]]) + centre
            + np.reshape(jitter, (4, 2)) * min(size))
    # a corner past the slab's edge (a turned square's diagonal reaches 0.3 sqrt(2) from the
    # centre) would make the joint another polygon than the quadrilateral
    assume(np.all((ring > 0.01) & (ring < 0.99)))
    turn = _rotation(axis, angle)
    blocks = [box(0, 0, -0.5, 1, 1, 0) @ turn.T, _prism(ring, lift, 0.4) @ turn.T]
    c = _detect(blocks, 3, 3)
    assert c.count == 9
    point, area, _ = _rows(c)
    back = point @ turn  # the points in the blocks' frame
    assert np.all(area > 0.0)
    assert back[:, 2] == pytest.approx(lift, abs=TOL)  # on the prism's face
    moments = _polygon_moments(ring - centre)
    assert _rule_moments(back[:, :2] - centre, area) == pytest.approx(moments, abs=TOL)
    assert {tuple(np.round(p, 9)) for p in back[:4, :2]} == {tuple(np.round(p, 9))
                                                             for p in ring}  # corners kept


# -- defaults, keys and bad input --------------------------------------------------------------


def test_dry_contacts_unchanged_by_another_laws_points():
    # a stack whose law keeps 2 points gets the same contacts, bit for bit, whether or not
    # another law of the model asks for more (which widens the keys of every contact);
    # in 2D and 3D
    cases = {2: ([_box2(0, 0, 1.0, 0.5), _box2(0.1, 0.5, 0.7, 0.5)],
                 [_box2(3, 0, 1.0, 0.5), _box2(3, 0.5, 1.0, 0.5)]),
             3: ([box(0, 0, 0, 1, 1, 1), box(0.5, 0.25, 1, 1.5, 1.25, 2)],
                 [box(5, 0, 0, 6, 1, 1), box(5, 0, 1, 6, 1, 2)])}
    for dim, (dry, other) in cases.items():
        found = []
        for points in (2, 3):
            b = sx.ModelBuilder(dim=dim)
            for k, vertices in enumerate(dry):
                b.add_block(vertices, density=1000.0, name=f"dry {k}", group="dry")
            for k, vertices in enumerate(other):
                b.add_block(vertices, density=1000.0, name=f"joint {k}", group="joint")
            b.set_law("dry", "dry", sx.ContactLaw(friction=0.5))
            b.set_law("joint", "joint", sx.ContactLaw(friction=0.5, points=points))
            b.set_law("dry", "joint", sx.ContactLaw(friction=0.5))
            model = b.finalize()
            c = Contacts(dim)
            detector_for(model, DetectionSettings(alert=ALERT)).detect(model.body_q0, c)
            dry_rows = c.candidate[: c.count] < 2
            found.append({f: getattr(c, f)[: c.count][dry_rows].copy()
                          for f in ("candidate", "antagonist", "point", "frame", "gap", "area")})
            found[-1]["order"] = np.argsort(c.key[: c.count][dry_rows])
        assert found[0].keys() == found[1].keys()
        for field in found[0]:
            assert np.array_equal(found[0][field], found[1][field]), (dim, field)


@pytest.mark.parametrize("dim", [2, 3])
def test_keys_of_a_block_at_rest_stay_from_step_to_step(dim):
    b = sx.ModelBuilder(dim=dim)
    if dim == 2:
        b.add_block(_box2(-1, -0.5, 2.0, 0.5), kind=sx.BodyKind.FIXED, group="ground")
        b.add_block(_box2(0, 0, 0.6, 0.4), density=2000.0)
    else:
        b.add_block(box(-1, -1, -0.5, 1, 1, 0), kind=sx.BodyKind.FIXED, group="ground")
        b.add_block(box(0, 0, 0, 0.6, 0.5, 0.4), density=2000.0)
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6, points=3))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    sim = sx.Simulation(b.finalize(), dt=1e-3)
    state = sim.initial_state()
    sim.step(state)
    keys = state.contacts.key[: state.contacts.count].copy()
    assert len(keys) == (3 if dim == 2 else 9)
    for _ in range(20):
        previous = state.contacts.copy()
        sim.step(state)
        c = state.contacts
        assert np.array_equal(c.key[: c.count], keys)
        # the warm start found every contact, so the impulses carried over
        assert c.copy().warm_start_from(previous) == len(keys)


@pytest.mark.parametrize("points", [4, 1, 17, 2.0])
def test_bad_point_counts_are_refused(points):
    with pytest.raises(InputError, match="points"):
        sx.ContactLaw(friction=0.5, points=points)


def test_3d_laws_take_at_most_three_points():
    b = sx.ModelBuilder(dim=3)
    b.add_block(box(0, 0, 0, 1, 1, 1), density=1000.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5, points=5))
    with pytest.raises(InputError, match="3D contacts take 2"):
        b.finalize()
