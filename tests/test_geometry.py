"""Unit and property tests of saxum.geometry2d (area, centroid, polar moment, validation).

Closed forms (any mechanics handbook; shoelace formulas as in the module docstring):
- rectangle b x h: A = b h, centroid at its centre, J = A (b^2 + h^2) / 12;
- triangle with sides a, b, c: A = |cross| / 2, centroid = vertex mean,
  J = A (a^2 + b^2 + c^2) / 36;
- regular n-gon of circumradius R: A = n R^2 sin(2 pi / n) / 2, centroid = centre,
  J = A R^2 (1 + 2 cos^2(pi / n)) / 6 (-> A R^2 / 2, the disc, as n -> infinity).
Tolerance: 1e-12 relative (round-off) unless stated.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import saxum as sx
from saxum.geometry2d import normalize_polygon, polygon_properties

REL = 1e-12


def props(vertices):
    return polygon_properties(normalize_polygon(vertices))


def rotate(points, angle, centre=(0.0, 0.0)):
    p = np.asarray(points, dtype=float) - centre
    c, s = math.cos(angle), math.sin(angle)
    return np.column_stack((c * p[:, 0] - s * p[:, 1], s * p[:, 0] + c * p[:, 1])) + centre


def regular_polygon(n, radius, centre=(0.0, 0.0), phase=0.0):
    phi = phase + 2.0 * math.pi * np.arange(n) / n
    return np.column_stack((centre[0] + radius * np.cos(phi), centre[1] + radius * np.sin(phi)))


# --- closed forms -----------------------------------------------------------------------------


@pytest.mark.parametrize(("x0", "y0", "b", "h"), [(0.0, 0.0, 1.0, 1.0), (-3.0, 2.0, 0.25, 0.065),
                                                  (1e3, -1e3, 2.0, 0.5), (0.0, 0.0, 1e-3, 5e-3)])
def test_rectangle(x0, y0, b, h):
    p = props([(x0, y0), (x0 + b, y0), (x0 + b, y0 + h), (x0, y0 + h)])
    area = b * h
    assert p.area == pytest.approx(area, rel=REL)
    assert p.centroid == pytest.approx([x0 + b / 2, y0 + h / 2], rel=REL, abs=REL * (b + h))
    assert p.polar_moment == pytest.approx(area * (b * b + h * h) / 12.0, rel=1e-10)


@pytest.mark.parametrize("tri", [[(0, 0), (1, 0), (0, 1)], [(0, 0), (4, 0), (1, 3)],
                                 [(-2.5, 1.0), (3.0, -0.5), (0.2, 7.0)]])
def test_triangle(tri):
    v = np.array(tri, dtype=float)
    p = props(v)
    e = v - np.roll(v, -1, axis=0)
    sides2 = (e**2).sum(axis=1)
    area = 0.5 * abs(e[0, 0] * e[1, 1] - e[0, 1] * e[1, 0])
    assert p.area == pytest.approx(area, rel=REL)
    assert p.centroid == pytest.approx(v.mean(axis=0), rel=REL, abs=1e-14)
    assert p.polar_moment == pytest.approx(area * sides2.sum() / 36.0, rel=REL)


def test_equilateral_triangle_polar_moment():
    s = 2.0
    v = [(0.0, 0.0), (s, 0.0), (s / 2, s * math.sqrt(3) / 2)]
    assert props(v).polar_moment == pytest.approx(math.sqrt(3) * s**4 / 48.0, rel=REL)


@pytest.mark.parametrize("n", [3, 4, 5, 6, 8, 12, 64])
def test_regular_polygon(n):
    radius, centre = 0.7, (1.5, -2.0)
    p = props(regular_polygon(n, radius, centre, phase=0.3))
    area = 0.5 * n * radius**2 * math.sin(2.0 * math.pi / n)
    assert p.area == pytest.approx(area, rel=REL)
    assert p.centroid == pytest.approx(centre, rel=REL)
    assert p.polar_moment == pytest.approx(
        area * radius**2 * (1.0 + 2.0 * math.cos(math.pi / n) ** 2) / 6.0, rel=1e-11)


def test_many_sided_polygon_tends_to_disc():
    radius = 1.3
    p = props(regular_polygon(720, radius))
    assert p.area == pytest.approx(math.pi * radius**2, rel=1e-4)
    assert p.polar_moment == pytest.approx(math.pi * radius**4 / 2.0, rel=1e-4)


def test_model_mass_and_inertia_use_density():
    b = sx.ModelBuilder()
    body = b.add_block([(0, 0), (0.4, 0), (0.4, 0.2), (0, 0.2)], density=2500.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.5))
    m = b.finalize()
    assert m.body_mass[body] == pytest.approx(2500.0 * 0.08, rel=REL)
    assert m.body_inertia[body] == pytest.approx(2500.0 * 0.08 * (0.16 + 0.04) / 12, rel=REL)
    assert m.body_q0[body] == pytest.approx([0.2, 0.1, 0.0], rel=REL)
    assert m.body_radius[body] == pytest.approx(math.hypot(0.2, 0.1), rel=REL)
    loc = m.vertex_local[m.body_vertex_start[body]:m.body_vertex_start[body + 1]]
    assert loc.mean(axis=0) == pytest.approx([0.0, 0.0], abs=1e-15)


# --- properties -------------------------------------------------------------------------------


@st.composite
def convex_polygons(draw):
    """Strictly convex polygons: 3 to 12 points on a rotated, shifted ellipse at increasing
    angles (every corner turns by well over the 1e-9 convexity threshold)."""
    n = draw(st.integers(3, 12))
    gaps = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n)))
    # points of an ellipse in angular order are in convex position; gaps in [0.05, 1] make
    # every angular step >= 2 pi / (20 n) >= 0.026 rad, so no corner is nearly straight
    angles = 2.0 * math.pi * np.cumsum(gaps) / gaps.sum()
    a = draw(st.floats(0.1, 5.0))
    b = draw(st.floats(0.1, 5.0))
    tilt = draw(st.floats(0.0, 2.0 * math.pi))
    cx = draw(st.floats(-10.0, 10.0))
    cy = draw(st.floats(-10.0, 10.0))
    pts = np.column_stack((a * np.cos(angles), b * np.sin(angles)))
    return rotate(pts, tilt) + (cx, cy)


def _same(p, q, *, centroid_shift=(0.0, 0.0), rel=1e-9):
    size = math.sqrt(p.area)
    assert q.area == pytest.approx(p.area, rel=rel)
    assert q.polar_moment == pytest.approx(p.polar_moment, rel=rel)
    assert np.abs(q.centroid - (p.centroid + centroid_shift)).max() <= rel * (
        size + np.abs(p.centroid).max())


@settings(max_examples=200, deadline=None)
@given(poly=convex_polygons())
def test_area_centroid_and_polar_moment_by_triangulation(poly):
    p = props(poly)
    assert p.area > 0.0 and p.polar_moment > 0.0
    v = normalize_polygon(poly)
    # the centroid lies inside: on the inner side of every CCW edge
    e = np.roll(v, -1, axis=0) - v
    d = p.centroid - v
    assert np.all(e[:, 0] * d[:, 1] - e[:, 1] * d[:, 0] > 0.0)
    # fan triangulation from the centroid with the triangle closed forms (independent of the
    # shoelace polar-moment sum): J_G = sum of (J_tri + A_tri |c_tri - C|^2), A = sum A_tri
    w = np.roll(v, -1, axis=0)
    area = 0.0
    polar = 0.0
    for a, b in zip(v, w, strict=True):
        tri = np.array([p.centroid, a, b])
        e = tri - np.roll(tri, -1, axis=0)
        at = 0.5 * (e[0, 0] * e[1, 1] - e[0, 1] * e[1, 0])
        assert at > 0.0
        ct = tri.mean(axis=0) - p.centroid
        area += at
        polar += at * (e**2).sum() / 36.0 + at * float(ct @ ct)
    assert area == pytest.approx(p.area, rel=1e-10)
    assert polar == pytest.approx(p.polar_moment, rel=1e-10)


@settings(max_examples=200, deadline=None)
@given(poly=convex_polygons(), dx=st.floats(-1e3, 1e3), dy=st.floats(-1e3, 1e3))
def test_translation_invariance(poly, dx, dy):
    _same(props(poly), props(poly + (dx, dy)), centroid_shift=(dx, dy), rel=1e-8)


@settings(max_examples=200, deadline=None)
@given(poly=convex_polygons(), angle=st.floats(-10.0, 10.0))
def test_rotation_invariance(poly, angle):
    p = props(poly)
    q = props(rotate(poly, angle))
    assert q.area == pytest.approx(p.area, rel=1e-9)
    assert q.polar_moment == pytest.approx(p.polar_moment, rel=1e-9)
    assert q.centroid == pytest.approx(rotate([p.centroid], angle)[0], rel=1e-9, abs=1e-9)


@settings(max_examples=200, deadline=None)
@given(poly=convex_polygons(), shift=st.integers(0, 11))
def test_vertex_order_reversal_and_cyclic_shift(poly, shift):
    p = props(poly)
    shifted = np.roll(poly, shift % len(poly), axis=0)
    _same(p, props(shifted), rel=1e-12)
    reversed_ = poly[::-1]
    v = normalize_polygon(reversed_)
    # normalized to counter-clockwise: positive signed area
    assert 0.5 * np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1]) > 0
    _same(p, polygon_properties(v), rel=1e-12)


@settings(max_examples=200, deadline=None)
@given(poly=convex_polygons(), k=st.floats(1e-3, 1e3))
def test_scaling(poly, k):
    p = props(poly)
    c = p.centroid
    q = props((poly - c) * k + c)
    assert q.area == pytest.approx(p.area * k**2, rel=1e-9)
    assert q.polar_moment == pytest.approx(p.polar_moment * k**4, rel=1e-9)


@settings(max_examples=200, deadline=None)
@given(poly=convex_polygons(), cut=st.integers(2, 11))
def test_additivity_over_a_split(poly, cut):
    """Cut along the chord from vertex 0 to vertex k: areas add, centroids average by area,
    polar moments add after the parallel-axis shift to the whole centroid."""
    v = normalize_polygon(poly)
    n = len(v)
    if n == 3:
        return  # a triangle has no inner chord
    k = 2 + cut % (n - 3)  # 2 <= k <= n - 2: both parts have >= 3 vertices
    part1, part2 = v[: k + 1], np.vstack((v[k:], v[:1]))
    whole, p1, p2 = props(v), props(part1), props(part2)
    assert p1.area + p2.area == pytest.approx(whole.area, rel=1e-10)
    c = (p1.area * p1.centroid + p2.area * p2.centroid) / whole.area
    assert c == pytest.approx(whole.centroid, rel=1e-9, abs=1e-9 * math.sqrt(whole.area))
    j = sum(p.polar_moment + p.area * float((p.centroid - c) @ (p.centroid - c))
            for p in (p1, p2))
    assert j == pytest.approx(whole.polar_moment, rel=1e-9)


def test_clockwise_input_is_reversed_and_ccw_kept():
    ccw = np.array([(0.0, 0.0), (1.0, 0.0), (1.0, 2.0), (0.0, 2.0)])
    assert np.array_equal(normalize_polygon(ccw), ccw)
    assert np.array_equal(normalize_polygon(ccw[::-1]), ccw)


# --- errors -----------------------------------------------------------------------------------


@pytest.mark.parametrize(("vertices", "words"), [
    ([(0, 0), (2, 0), (1, 0.5), (2, 2), (0, 2)], "not strictly convex"),      # reflex corner
    ([(0, 0), (1, 0), (2, 0), (2, 1), (0, 1)], "collinear"),                   # straight corner
    ([(0, 0), (1, 1)], "at least 3 vertices"),
    ([], "(x, y) pairs"),
    ([(0, 0), (1, 1), (2, 2)], "zero area"),                                   # collinear
    ([(1, 1), (1, 1), (1, 1)], "zero area"),                                   # one point
    ([(0, 0), (1, 0), (float("nan"), 1)], "NaN"),
    ([(0, 0), (1, 0), (1, float("inf"))], "infinity"),
    ([(0, 0), (1, 0), (1, 0), (1, 1), (0, 1)], "coincide"),                    # repeated vertex
    ([(0, 0, 0), (1, 0, 0), (1, 1, 0)], "(x, y) pairs"),
])
def test_bad_polygons_raise_input_error_naming_the_block(vertices, words):
    with pytest.raises(sx.InputError) as info:
        normalize_polygon(vertices, name="stone 17")
    msg = str(info.value)
    assert "stone 17" in msg
    assert words in msg
