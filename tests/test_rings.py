"""Arches of several concentric rings (saxum.structures.arch_rings): geometry, names and
groups, the scenario keys, 3D extrusion, bad input."""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.scenario import parse_scenario
from saxum.structures import ArchShape, arch, arch3d, arch_ring, arch_rings

SHAPES = {
    "semicircular": ArchShape.semicircular(span=2.0, thickness=0.3),
    "segmental": ArchShape.segmental(span=4.0, rise=1.0, thickness=0.4),
    "pointed": ArchShape.pointed(span=2.0, thickness=0.3, eccentricity=0.5),
    "elliptical": ArchShape.elliptical(span=3.0, rise=1.0, thickness=0.3),
    "basket": ArchShape.basket_handle(span=3.0, rise=1.0, thickness=0.3),
    "flat": ArchShape.flat(span=2.0, depth=0.4),
}


def _area(poly) -> float:
    """|area| [m^2] of a polygon (shoelace; a flat arch's intrados has none)."""
    x, y = np.asarray(poly, dtype=np.float64).T
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


@pytest.mark.parametrize("name", SHAPES)
@pytest.mark.parametrize("rings, voussoirs, stagger", [(2, 8, False), (2, 9, True),
                                                       (3, [9, 11, 12], True)])
def test_rings_tile_the_arch(name, rings, voussoirs, stagger):
    """The rings' voussoirs (convex, or arch_rings raises) fill the region between the
    outline and the intrados exactly: no gap, no overlap between rings."""
    cut = arch_rings(SHAPES[name], voussoirs, rings, ring_stagger=stagger)
    assert sorted(set(cut.rings)) == list(range(1, rings + 1))
    inner = [p[0] for p, r in zip(cut.voussoirs, cut.rings, strict=True) if r == 1]
    inner.append(cut.voussoirs[cut.rings.index(2) - 1][-1])
    region = _area(cut.outline) - _area(np.array(inner))
    total = sum(_area(p) for p in cut.voussoirs)
    assert total == pytest.approx(region, rel=1e-12, abs=1e-14)


def test_aligned_rings_split_each_voussoir_of_the_single_ring():
    """With aligned joints, each voussoir of the one-ring arch is split into one per ring,
    at the given thicknesses."""
    shape = SHAPES["semicircular"]
    one = arch_ring(shape, 7)
    two = arch_ring(shape, 7, rings=2, ring_thicknesses=[0.1, 0.2])
    for k, whole in enumerate(one.voussoirs):
        a, b = two.voussoirs[k], two.voussoirs[7 + k]
        assert _area(a) + _area(b) == pytest.approx(_area(whole), rel=1e-12)
        np.testing.assert_allclose(a[0], whole[0], atol=1e-15)
        np.testing.assert_allclose(b[1], whole[1], atol=1e-15)
        assert math.dist(a[0], a[1]) == pytest.approx(0.1, rel=1e-12)


def test_staggered_ring_has_half_voussoirs_at_the_springings_and_is_symmetric():
    cut = arch_rings(SHAPES["semicircular"], 6, 2, ring_stagger=True)
    assert cut.rings.count(1) == 6 and cut.rings.count(2) == 7
    outer = [p for p, r in zip(cut.voussoirs, cut.rings, strict=True) if r == 2]
    # half of a whole one, but for the chords: the whole voussoir's extrados chord cuts more
    assert _area(outer[0]) == pytest.approx(0.5 * _area(outer[1]), rel=0.05)
    for p, q in zip(cut.voussoirs[:6], cut.voussoirs[5::-1], strict=True):
        np.testing.assert_array_equal(np.sort(p[:, 0]), np.sort(-q[:, 0]))


def test_one_ring_is_the_arch_as_before():
    shape = SHAPES["pointed"]
    a, b = arch_ring(shape, 9), arch_ring(shape, 9, rings=1)
    for p, q in zip(a.voussoirs, b.voussoirs, strict=True):
        np.testing.assert_array_equal(p, q)
    assert b.rings == ()


def test_ring_names_groups_and_3d():
    model = arch(SHAPES["semicircular"], voussoirs=5, rings=2, ring_stagger=True)
    assert "voussoir ring 1" in model.group_names and "voussoir ring 2" in model.group_names
    assert "ring 2 voussoir 6" in model.body_name
    solid = arch3d(SHAPES["semicircular"], voussoirs=5, depth=1.0, pieces=2, stagger=True,
                   rings=2)
    # every other voussoir (counted on through both rings) in 3 pieces along the depth
    assert solid.dim == 3 and solid.body_count == 3 + 10 * 2 + 5


def test_scenario_rings_and_ring_interface_law():
    text = """
[structure]
type = "arch"
shape = "semicircular"
span = 2.0
thickness = 0.3
voussoirs = 7
rings = 2
ring_thicknesses = [0.1, 0.2]
ring_stagger = true

[[laws]]
groups = ["*", "*"]
friction = 0.6

[[laws]]
groups = ["voussoir ring 1", "voussoir ring 2"]
friction = 0.3

[output]
duration = 0.1
"""
    model = parse_scenario(text).build_model()
    g1, g2 = (model.group_names.index(f"voussoir ring {i}") for i in (1, 2))
    assert model.laws[model.group_law[g1, g2]].friction == 0.3
    # the given coefficient, stored: 1e-15 allows only a different float
    assert model.laws[model.group_law[g1, g1]].friction == pytest.approx(0.6, rel=1e-15)
    assert model.body_count == 3 + 7 + 8


@pytest.mark.parametrize("kwargs, words", [
    ({"rings": 0}, ["rings"]),
    ({"rings": 2, "ring_thicknesses": [0.1, 0.1]}, ["ring_thicknesses", "add up", "0.3"]),
    ({"rings": 2, "ring_thicknesses": [0.3, 0.0]}, ["ring_thicknesses[1]"]),
    ({"rings": 2, "ring_thicknesses": [0.3]}, ["ring_thicknesses", "one thickness"]),
    ({"rings": 2, "joints": "vertical"}, ["joints", "radial"]),
    ({"rings": 2, "voussoirs": [7, 8, 9]}, ["voussoirs", "one per ring"]),
    ({"rings": 2, "voussoirs": [7, 0]}, ["voussoirs[1]"]),
    ({"rings": 2, "ring_thicknesses": [0.002, 0.298], "voussoirs": [9, 4],
      "ring_stagger": True}, ["ring 1", "thinner", "ring_thicknesses"]),
])
def test_bad_rings_name_the_parameter(kwargs, words):
    options = {"voussoirs": 7, **kwargs}
    with pytest.raises(sx.InputError) as info:
        arch(SHAPES["semicircular"], **options)
    for word in words:
        assert word in str(info.value), (word, str(info.value))
