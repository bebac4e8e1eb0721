"""Arches of equal voussoirs: any ring between an intrados and an extrados curve (ArchShape:
semicircular, circular of any embrace, segmental, pointed, elliptical, basket-handle, flat),
cut along radial or vertical joints, alone, on fixed supports or on piers.

The older semicircular_arch family (by the mean radius) is kept for the scenarios and
validation tests that use it. Every arch numbers its voussoirs from the left springing
("voussoir 1" is the leftmost), as mechanism reports and pictures name them.
"""

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..errors import InputError, plain
from ..laws import ContactLaw, LawKind
from ..model import BodyKind, Model, ModelBuilder
from ._common import (
    Assembly,
    add_ground,
    check_convex,
    check_count,
    check_positive,
    clean,
    model_form,
)
from .piers import pier_polygons

__all__ = ["ArchShape", "Ring", "add_arch", "add_semicircular_arch", "add_supported_arch",
           "add_supported_semicircular_arch", "arch", "arch_ring", "arch_rings",
           "semicircular_arch"]

Curve = Callable[[np.ndarray], np.ndarray]


def add_semicircular_arch(
    builder: ModelBuilder,
    *,
    radius: float,
    thickness: float,
    voussoirs: int,
    density: float = 2000.0,
    centre: tuple[float, float] = (0.0, 0.0),
    group: str = "voussoir",
) -> list[int]:
    """Add the voussoirs of a semicircular arch; returns their body indices, left to right
    (named "voussoir 1" at the left springing to "voussoir <voussoirs>" at the right one).

    radius: mean radius R [m] (centre line of the ring); thickness t [m] of the ring;
    voussoirs: number of equal voussoirs, each spanning pi/voussoirs of the ring, with radial
    joints; intrados and extrados are chords between joint ends. The springings lie on the
    horizontal line through `centre`.
    """
    check_positive(radius=radius, thickness=thickness)
    if not thickness < 2.0 * radius:
        raise InputError(f"thickness must be less than 2 radius (the mean radius R = "
                         f"{radius:g} m: the intrados radius R - t/2 must stay > 0), got "
                         f"thickness={thickness:g}")
    check_count("voussoirs", voussoirs)
    cx, cy = centre
    r_in, r_out = radius - 0.5 * thickness, radius + 0.5 * thickness
    phi = np.linspace(0.0, math.pi, voussoirs + 1)
    cos, sin = np.cos(phi), np.sin(phi)
    # Mirror the right half so that the arch is exactly symmetric and both springings are level.
    cos[::-1][: (voussoirs + 1) // 2] = -cos[: (voussoirs + 1) // 2]
    sin[::-1][: (voussoirs + 1) // 2] = sin[: (voussoirs + 1) // 2]
    if voussoirs % 2 == 0:
        cos[voussoirs // 2], sin[voussoirs // 2] = 0.0, 1.0
    bodies = []
    for n, k in enumerate(reversed(range(voussoirs))):  # joint angles run right to left
        a, b = k, k + 1
        verts = [
            (cx + r_in * cos[a], cy + r_in * sin[a]),
            (cx + r_out * cos[a], cy + r_out * sin[a]),
            (cx + r_out * cos[b], cy + r_out * sin[b]),
            (cx + r_in * cos[b], cy + r_in * sin[b]),
        ]
        bodies.append(builder.add_block(verts, density=density, group=group,
                                        name=f"voussoir {n + 1}"))
    return bodies


def add_supported_semicircular_arch(
    builder: ModelBuilder, *, radius: float, thickness: float, voussoirs: int,
    density: float = 2000.0,
) -> list[int]:
    """A fixed support block ("support", t deep, 5 R wide, so that a collapsing arch falls
    onto it) and a semicircular arch on it (add_semicircular_arch, groups "support" and
    "voussoir"); returns the voussoirs' body indices."""
    half = 2.5 * radius
    builder.add_block([(-half, -thickness), (half, -thickness), (half, 0.0), (-half, 0.0)],
                      kind=BodyKind.FIXED, group="support", name="support")
    return add_semicircular_arch(builder, radius=radius, thickness=thickness,
                                 voussoirs=voussoirs, density=density)


def semicircular_arch(
    *,
    radius: float,
    thickness: float,
    voussoirs: int,
    density: float = 2000.0,
    friction: float = 0.6,
    law: LawKind = LawKind.GAP_SIGNORINI_COULOMB,
    gravity: tuple[float, float] = (0.0, -9.81),
) -> Model:
    """A semicircular arch on its support (add_supported_semicircular_arch), friction mu [-] on
    every joint. Voussoirs are bodies 1..voussoirs, left springing first; body 0 is the
    support."""
    builder = ModelBuilder(gravity=gravity)
    add_supported_semicircular_arch(builder, radius=radius, thickness=thickness,
                                    voussoirs=voussoirs, density=density)
    contact = ContactLaw(friction=friction, kind=law)
    builder.set_law("voussoir", "voussoir", contact)
    builder.set_law("voussoir", "support", contact)
    return builder.finalize()


def _bracket(f: Callable[[np.ndarray], np.ndarray], targets: np.ndarray, lo: float,
             hi: float) -> tuple[np.ndarray, np.ndarray]:
    """Bisection to round-off for f(x) = targets, f increasing (vectorised): the final
    brackets (a, b), f(a) < target <= f(b) where f jumps."""
    a = np.full(len(targets), lo)
    b = np.full(len(targets), hi)
    for _ in range(64):
        mid = 0.5 * (a + b)
        below = f(mid) < targets
        a = np.where(below, mid, a)
        b = np.where(below, b, mid)
    return a, b


def _meet(c1: np.ndarray, r1: float, c2: np.ndarray, r2: float, towards: np.ndarray,
          ) -> np.ndarray:
    """The intersection of two circles (centre, radius) [m] farther along `towards`."""
    d = c2 - c1
    dist = math.hypot(*d)
    a = (r1 * r1 - r2 * r2 + dist * dist) / (2.0 * dist)
    h = math.sqrt(max(r1 * r1 - a * a, 0.0))
    base = c1 + a * d / dist
    perp = np.array([-d[1], d[0]]) / dist
    return max((base + h * perp, base - h * perp), key=lambda p: float(p @ towards))


@dataclass(frozen=True)
class ArchShape:
    """The ring of an arch, between its intrados and its extrados, in the arch's own frame.

    intrados(s), extrados(s): s (array, in [0, 1]) -> points (n, 2) [m], from the left springing
    (s = 0) to the right one (s = 1). Equal steps of s are voussoirs of equal intrados length,
    and the segment from intrados(s) to extrados(s) is the radial joint at s (normal to the
    intrados). corners: values of s where the extrados has a corner (the crown of a pointed
    arch), extrados(corner) being the corner; a voussoir that spans one gets it as a vertex.
    symmetric: the ring is its own mirror image about x = 0; the left half is then mirrored
    so that the voussoirs are exactly symmetric. Both curves must be convex (bulging away from
    the opening) and the extrados's x must increase with s.

    The named shapes below put the intrados springings at (-span/2, 0) and (span/2, 0); span
    and rise are those of the intrados (the clear opening), thickness [m] is that of the ring,
    measured along the joints.
    """

    intrados: Curve
    extrados: Curve
    corners: tuple[float, ...] = ()
    symmetric: bool = False
    thickness: float | None = None
    """The ring's thickness [m] the shape was made with (None: measured along the springing
    joint where needed)."""

    @classmethod
    def _arcs(cls, arcs: list[tuple[np.ndarray, float, float, float]],
              thickness: float) -> "ArchShape":
        """A symmetric ring whose intrados is a chain of circular arcs (centre [m], radius [m],
        start and end angle [rad]) and whose extrados is the chain of concentric arcs of radius
        r + thickness; where two arcs meet at an angle, their extrados arcs meet at a corner."""
        centre = np.array([a[0] for a in arcs], dtype=np.float64)
        radius = np.array([a[1] for a in arcs])
        phi0, phi1 = np.array([a[2] for a in arcs]), np.array([a[3] for a in arcs])
        length = radius * np.abs(phi1 - phi0)
        cum = np.concatenate(([0.0], np.cumsum(length)))
        corners = {}
        for j in range(1, len(arcs)):
            if abs(phi1[j - 1] - phi0[j]) > 1e-12:
                towards = np.array([math.cos(phi1[j - 1]) + math.cos(phi0[j]),
                                    math.sin(phi1[j - 1]) + math.sin(phi0[j])])
                corners[float(cum[j] / cum[-1])] = _meet(
                    centre[j - 1], radius[j - 1] + thickness, centre[j], radius[j] + thickness,
                    towards)

        def curve_at(offset: float) -> Curve:
            def curve(s):
                s = np.atleast_1d(np.asarray(s, dtype=np.float64))
                at = s * cum[-1]
                i = np.clip(np.searchsorted(cum, at, side="right") - 1, 0, len(arcs) - 1)
                phi = phi0[i] + (phi1[i] - phi0[i]) * ((at - cum[i]) / length[i])
                pts = centre[i] + (radius[i] + offset)[:, None] * np.column_stack(
                    (np.cos(phi), np.sin(phi)))
                if offset:
                    for sc, point in corners.items():
                        pts[s == sc] = point
                return pts
            return curve

        return cls(curve_at(0.0), curve_at(thickness), tuple(corners), symmetric=True,
                   thickness=thickness)

    @classmethod
    def circular(cls, *, span: float, thickness: float,
                 embrace: float = math.pi) -> "ArchShape":
        """A circular arch whose intrados spans `span` [m] and subtends the embrace angle
        [rad], 0 < embrace <= pi (pi: semicircular; less: segmental); radial joints."""
        check_positive(span=span, thickness=thickness)
        if not (isinstance(embrace, int | float) and 0.0 < embrace <= math.pi):
            raise InputError(f"embrace must be an angle in (0, pi] [rad], got "
                             f"{plain(embrace)}")
        half = 0.5 * embrace
        r = 0.5 * span / math.sin(half)
        centre = np.array([0.0, 0.0 if embrace == math.pi else -r * math.cos(half)])
        return cls._arcs([(centre, r, 0.5 * math.pi + half, 0.5 * math.pi - half)], thickness)

    @classmethod
    def semicircular(cls, *, span: float, thickness: float) -> "ArchShape":
        """A semicircular arch: intrados radius span / 2 [m]."""
        return cls.circular(span=span, thickness=thickness)

    @classmethod
    def segmental(cls, *, span: float, rise: float, thickness: float) -> "ArchShape":
        """A segmental arch of intrados span and rise [m], 0 < rise <= span / 2: a circular
        arch of embrace 4 atan(2 rise / span), radius (span^2 / 4 + rise^2) / (2 rise)."""
        check_positive(span=span, rise=rise, thickness=thickness)
        if rise > 0.5 * span:
            raise InputError(f"rise must be in (0, span/2 = {0.5 * span:g}] [m], got {rise:g}")
        return cls.circular(span=span, thickness=thickness,
                            embrace=4.0 * math.atan(2.0 * rise / span))

    @classmethod
    def pointed(cls, *, span: float, thickness: float, eccentricity: float) -> "ArchShape":
        """A pointed (two-centred) arch: each half of the intrados is an arc whose centre lies
        on the springing line at eccentricity * span / 2 [m] from the axis, on the other side;
        radius (1 + eccentricity) span / 2, crown height span / 2 sqrt(1 + 2 eccentricity).
        eccentricity >= 0: 0 semicircular, 1 equilateral (centres at the springings), > 1
        lancet. The extrados arcs are concentric and meet at the extrados crown."""
        check_positive(span=span, thickness=thickness)
        if not (isinstance(eccentricity, int | float) and 0.0 <= eccentricity < math.inf):
            raise InputError(f"eccentricity must be a finite number >= 0, got "
                             f"{plain(eccentricity)}")
        c = 0.5 * eccentricity * span
        r = 0.5 * (1.0 + eccentricity) * span
        gamma = math.acos(eccentricity / (1.0 + eccentricity))
        return cls._arcs([(np.array([c, 0.0]), r, math.pi, math.pi - gamma),
                          (np.array([-c, 0.0]), r, gamma, 0.0)], thickness)

    @classmethod
    def basket_handle(cls, *, span: float, rise: float, thickness: float) -> "ArchShape":
        """A three-centred (basket-handle) arch of intrados span and rise [m],
        0 < rise < span / 2, by the classical construction that approximates the ellipse: the
        perpendicular bisector of the part of the chord from springing to crown that remains
        after taking off (span/2 - rise) at the crown gives the side centres on the springing
        line; the crown arc is tangent to both side arcs."""
        check_positive(span=span, rise=rise, thickness=thickness)
        a, f = 0.5 * span, rise
        if f >= a:
            raise InputError(f"rise must be in (0, span/2 = {a:g}) [m] for a basket-handle "
                             f"arch, got {rise:g}; use a semicircular or elliptical arch")
        chord = math.hypot(a, f)
        k = 0.5 * (chord + a - f)
        mx, my = -k * a / chord, f - k * f / chord
        r1 = a + mx + my * f / a
        r2 = ((a - r1) ** 2 + f * f - r1 * r1) / (2.0 * (f - r1))
        alpha = math.atan2(r2 - f, a - r1)
        return cls._arcs([(np.array([r1 - a, 0.0]), r1, math.pi, math.pi - alpha),
                          (np.array([0.0, f - r2]), r2, math.pi - alpha, alpha),
                          (np.array([a - r1, 0.0]), r1, alpha, 0.0)], thickness)

    @classmethod
    def elliptical(cls, *, span: float, rise: float, thickness: float) -> "ArchShape":
        """A semi-elliptical arch: intrados semi-axes span / 2 and rise [m] (any ratio);
        extrados the parallel curve at `thickness` [m] along the normals, which are the joints.
        The intrados length is b E(theta | 1 - a^2 / b^2) (incomplete elliptic integral of the
        second kind, scipy.special.ellipeinc) for the point (-a cos theta, b sin theta)."""
        from scipy.special import ellipeinc  # here: 0.4 s of import that other runs skip

        check_positive(span=span, rise=rise, thickness=thickness)
        a, b = 0.5 * span, rise
        m = 1.0 - (a / b) ** 2
        total = b * float(ellipeinc(math.pi, m))

        def theta(s):
            s = np.atleast_1d(np.asarray(s, dtype=np.float64))
            lo, hi = _bracket(lambda t: b * ellipeinc(t, m), s * total, 0.0, math.pi)
            return np.where(s <= 0.0, 0.0, np.where(s >= 1.0, math.pi, 0.5 * (lo + hi)))

        def intrados(s):
            th = theta(s)
            return np.column_stack((-a * np.cos(th), b * np.sin(th)))

        def extrados(s):
            th = theta(s)
            n = np.column_stack((-b * np.cos(th), a * np.sin(th)))
            n /= np.hypot(n[:, 0], n[:, 1])[:, None]
            return np.column_stack((-a * np.cos(th), b * np.sin(th))) + thickness * n

        return cls(intrados, extrados, symmetric=True, thickness=thickness)

    @classmethod
    def flat(cls, *, span: float, depth: float, skewback: float = math.radians(20.0),
             ) -> "ArchShape":
        """A flat (jack) arch: straight intrados and extrados `depth` [m] apart, joints that
        converge to one point below the crown, the springing joints leaning out by `skewback`
        [rad] from the vertical, 0 < skewback < pi/2."""
        check_positive(span=span, depth=depth)
        if not (isinstance(skewback, int | float) and 0.0 < skewback < 0.5 * math.pi):
            raise InputError(f"skewback must be an angle in (0, pi/2) [rad], got "
                             f"{plain(skewback)}")
        focus = 0.5 * span / math.tan(skewback)

        def intrados(s):
            x = span * (np.atleast_1d(np.asarray(s, dtype=np.float64)) - 0.5)
            return np.column_stack((x, np.zeros_like(x)))

        def extrados(s):
            x = span * (np.atleast_1d(np.asarray(s, dtype=np.float64)) - 0.5)
            return np.column_stack((x * (focus + depth) / focus, np.full_like(x, depth)))

        return cls(intrados, extrados, symmetric=True, thickness=depth)


class Ring(NamedTuple):
    """Voussoirs [m] from the left, the outline of ring and opening together (a convex
    polygon: springing points, extrados), and the springing faces (intrados point, extrados
    point) at the left and the right."""

    voussoirs: list[np.ndarray]
    outline: np.ndarray
    left: tuple[np.ndarray, np.ndarray]
    right: tuple[np.ndarray, np.ndarray]
    rings: tuple[int, ...] = ()
    """The ring (1 the intrados ring) of each voussoir when the arch has several; else ()."""


def arch_ring(shape: ArchShape, voussoirs: int | Sequence[int], joints: str = "radial",
              origin: tuple[float, float] = (0.0, 0.0), *, rings: int = 1,
              ring_thicknesses: Sequence[float] | None = None,
              ring_stagger: bool = False) -> Ring:
    """Cut `shape` into `voussoirs` voussoirs of equal intrados length along radial joints
    (intrados(s) to extrados(s)) or vertical ones (the springing faces stay as the shape has
    them), and move it by `origin` [m]. Neighbouring voussoirs share the same joint points.

    rings > 1: the ring is first divided into that many concentric rings (see arch_rings())."""
    if rings != 1 or ring_thicknesses is not None:
        return arch_rings(shape, voussoirs, rings, ring_thicknesses, ring_stagger, joints,
                          origin)
    if not isinstance(voussoirs, int) and isinstance(voussoirs, Sequence):
        if len(voussoirs) != 1:
            raise InputError(f"voussoirs gives {len(voussoirs)} counts for rings=1; give one")
        voussoirs = voussoirs[0]
    check_count("voussoirs", voussoirs)
    if joints not in ("radial", "vertical"):
        raise InputError(f"joints must be 'radial' or 'vertical', got {joints!r}")
    n = int(voussoirs)
    s = np.arange(n + 1) / n
    for c in shape.corners:
        s[np.abs(s - c) < 1e-9] = c
    corners = _extrados_corners(shape)
    m = n // 2 + 1 if shape.symmetric else n + 1
    inner = np.array(shape.intrados(s[:m]), dtype=np.float64)
    outer = np.array(shape.extrados(s[:m]), dtype=np.float64)
    if shape.symmetric and n % 2 == 0:
        inner[n // 2, 0] = outer[n // 2, 0] = 0.0
    u = s[:m].copy()
    cut = np.arange(1, min(m, n))
    if joints == "vertical" and cut.size:
        x = inner[cut, 0]
        lo, hi = _bracket(lambda v: shape.extrados(v)[:, 0], x, 0.0, 1.0)
        u[cut] = 0.5 * (lo + hi)
        outer[cut] = shape.extrados(u[cut])
        outer[cut, 0] = x
        for j, k in enumerate(cut):
            for c, point in corners.items():
                if lo[j] - 1e-9 <= c <= hi[j] + 1e-9:
                    # The line passes where the extrados turns its corner, between the ends of
                    # the arcs and the corner: take the chord to the corner there, as the
                    # voussoirs do, and put the corner in the voussoir on its side.
                    side = -1.0 if x[j] < point[0] else 1.0
                    end = shape.extrados(np.array([lo[j] if side < 0 else hi[j]]))[0]
                    if abs(x[j] - point[0]) <= 1e-9 * abs(end[0] - point[0]):
                        outer[k], u[k] = point, c
                    else:
                        t = (x[j] - point[0]) / (end[0] - point[0])
                        outer[k] = (x[j], point[1] + t * (end[1] - point[1]))
                        u[k] = c + side * 1e-10
    if shape.symmetric:
        back = np.arange(n - m, -1, -1)
        inner = np.vstack((inner, inner[back] * [-1.0, 1.0]))
        outer = np.vstack((outer, outer[back] * [-1.0, 1.0]))
        u = np.concatenate((u, 1.0 - u[back]))
    shift = np.asarray(origin, dtype=np.float64)
    inner, outer = inner + shift, outer + shift
    polys, top = [], [inner[0], outer[0]]
    for k in range(n):
        between = [corners[c] + shift for c in sorted(corners)
                   if u[k] + 1e-12 < c < u[k + 1] - 1e-12]
        polys.append(np.array([inner[k], outer[k], *between, outer[k + 1], inner[k + 1]]))
        top += [*between, outer[k + 1]]
    check_convex(polys, [f"voussoir {k + 1}" for k in range(n)],
                 f"voussoirs={n} with joints={joints!r} gives it that shape; use more voussoirs")
    outline = clean(np.array([*top, inner[n]]), float(np.ptp(top, axis=0).max()))
    return Ring(polys, outline, (inner[0], outer[0]), (inner[n], outer[n]))


def _extrados_corners(shape: ArchShape) -> dict[float, np.ndarray]:
    """The extrados' corners [m] by their s [-] (a symmetric shape's crown on x = 0)."""
    corners = {}
    for c in shape.corners:
        corners[c] = np.array(shape.extrados(np.array([c]))[0], dtype=np.float64)
        if shape.symmetric and c == 0.5:
            corners[c][0] = 0.0
    return corners


def _mirror_halves(pts: np.ndarray) -> np.ndarray:
    """pts (k, 2) made exactly symmetric about x = 0 by index, in place: the right half the
    left one mirrored, a middle point on x = 0."""
    half = len(pts) // 2
    pts[len(pts) - half:] = pts[:half][::-1] * [-1.0, 1.0]
    if len(pts) % 2:
        pts[half, 0] = 0.0
    return pts


def _ring_fractions(shape: ArchShape, rings: int,
                    ring_thicknesses: Sequence[float] | None) -> np.ndarray:
    """The boundaries between rings as fractions [-] of the joints, 0 (intrados) to 1."""
    check_count("rings", rings)
    if ring_thicknesses is None:
        return np.arange(rings + 1) / rings
    if isinstance(ring_thicknesses, str) or not isinstance(ring_thicknesses, Sequence) or len(
            ring_thicknesses) != rings:
        raise InputError(f"ring_thicknesses must list one thickness [m] per ring ({rings}), "
                         f"got {plain(ring_thicknesses)}")
    check_positive(**{f"ring_thicknesses[{i}]": t for i, t in enumerate(ring_thicknesses)})
    total = shape.thickness
    if total is None:
        inner, outer = shape.intrados(np.array([0.0]))[0], shape.extrados(np.array([0.0]))[0]
        total = math.hypot(*(outer - inner))
    given = math.fsum(ring_thicknesses)
    if abs(given - total) > 1e-6 * total:
        raise InputError(f"ring_thicknesses add up to {given:g} m, not to the arch's "
                         f"thickness {total:g} m; make them add up to it")
    return np.concatenate(([0.0], np.cumsum(ring_thicknesses) / given))


def _ring_joints(n: int, shifted: bool) -> np.ndarray:
    """Joint positions s [-] of a ring of n voussoirs, exactly symmetric (s[-1 - k] is
    1 - s[k]); shifted: by half a voussoir, with a half voussoir at each springing."""
    s = (np.arange(n) + 0.5) / n if shifted else np.arange(n + 1) / n
    if shifted:
        s = np.concatenate(([0.0], s, [1.0]))
    half = (len(s) + 1) // 2
    s[len(s) - half:] = (1.0 - s[:half])[::-1]
    if len(s) % 2:
        s[len(s) // 2] = 0.5
    return s


def arch_rings(shape: ArchShape, voussoirs: int | Sequence[int], rings: int,
               ring_thicknesses: Sequence[float] | None = None, ring_stagger: bool = False,
               joints: str = "radial", origin: tuple[float, float] = (0.0, 0.0)) -> Ring:
    """An arch of several concentric rings (brick arches in rowlock courses), radial joints.

    The ring of `shape` is divided along every joint into `rings` rings of equal thickness, or
    of ring_thicknesses [m] from the intrados (adding up to the thickness); the boundary
    between rings at a fraction f of the thickness is the curve intrados(s) + f (extrados(s) -
    intrados(s)). Each ring is cut into `voussoirs` voussoirs (one count for all rings, or one
    per ring) of equal length along the joints' s; with ring_stagger, the joints of every
    other ring (the 2nd, 4th, ...) are shifted by half a voussoir (a half voussoir at each of
    its springings, so it has one voussoir more). The boundary between two rings is the
    polyline through the joint ends of the outer ring on that curve: the outer ring's
    voussoirs keep a straight intrados, and the inner ring's joints end on it (so both sides
    of a boundary are the same line, and every voussoir is convex). Voussoirs from the inner
    ring out, each from the left; Ring.rings gives each one's ring.
    """
    if joints != "radial":
        raise InputError(f"joints={joints!r} with rings={rings}: an arch of several rings has "
                         f"radial joints only (the rings' joints would not meet the ring "
                         f"boundaries square); use joints='radial' or rings=1")
    fractions = _ring_fractions(shape, rings, ring_thicknesses)
    counts = list(voussoirs) if isinstance(voussoirs, Sequence) else [voussoirs] * rings
    if len(counts) != rings:
        raise InputError(f"voussoirs must be one count or one per ring ({rings}), got "
                         f"{plain(voussoirs)}")
    for i, n in enumerate(counts):
        check_count(f"voussoirs[{i}]" if isinstance(voussoirs, Sequence) else "voussoirs", n)
    s = [_ring_joints(int(n), ring_stagger and i % 2 == 1) for i, n in enumerate(counts)]

    def points(f: float, at: np.ndarray) -> np.ndarray:
        inner, outer = shape.intrados(at), shape.extrados(at)
        pts = np.array(inner + f * (outer - inner), dtype=np.float64)
        # mirror by index, as _ring_joints made s
        return _mirror_halves(pts) if shape.symmetric else pts

    corners = _extrados_corners(shape)
    shift = np.asarray(origin, dtype=np.float64)
    polys, ring_of, names = [], [], []
    for i in range(rings):
        bottom = points(fractions[i], s[i])
        if i == rings - 1:
            top = points(1.0, s[i])
            between = [[corners[c] for c in sorted(corners) if lo + 1e-12 < c < hi - 1e-12]
                       for lo, hi in zip(s[i][:-1], s[i][1:], strict=True)]
        else:
            above, line = s[i + 1], points(fractions[i + 1], s[i + 1])
            direction = points(1.0, s[i]) - points(0.0, s[i])
            top = np.empty_like(bottom)
            for k, sk in enumerate(s[i]):
                j = int(np.searchsorted(above, sk, side="right")) - 1
                if abs(above[j] - sk) <= 1e-12:
                    top[k] = line[j]
                    continue
                a, b = line[j], line[j + 1]
                # bottom[k] + x direction[k] on the chord a + y (b - a)
                x, _ = np.linalg.solve(np.column_stack((direction[k], a - b)), a - bottom[k])
                top[k] = bottom[k] + x * direction[k]
            between = [[line[j] for j in range(len(above)) if lo + 1e-12 < above[j] < hi - 1e-12]
                       for lo, hi in zip(s[i][:-1], s[i][1:], strict=True)]
            if shape.symmetric:
                _mirror_halves(top)
        if np.any(np.einsum("kd,kd->k", top - bottom, points(1.0, s[i]) - points(0.0, s[i]))
                  <= 0.0):
            raise InputError(f"ring {i + 1} is thinner than the sag of ring {i + 2}'s "
                             f"voussoirs over it (its joints would not reach the boundary); "
                             f"make it thicker (ring_thicknesses) or give ring {i + 2} more "
                             f"voussoirs")
        for k in range(len(s[i]) - 1):
            # a straight boundary (a flat arch's) needs no vertex where the other ring's joint is
            chord = top[k + 1] - top[k]
            between[k] = [p for p in between[k] if abs(chord[0] * (p[1] - top[k][1]) - chord[1]
                          * (p[0] - top[k][0])) > 1e-9 * (chord @ chord)]
            polys.append(np.array([bottom[k], top[k], *between[k], top[k + 1], bottom[k + 1]])
                         + shift)
            ring_of.append(i + 1)
            names.append(f"ring {i + 1} voussoir {k + 1}")
        if i == 0:
            inner = bottom + shift
        if i == rings - 1:
            outline_top = [inner[0], top[0] + shift]
            for k in range(len(s[i]) - 1):
                outline_top += [*(p + shift for p in between[k]), top[k + 1] + shift]
            outer = top + shift
    check_convex(polys, names, f"rings={rings} with voussoirs={plain(voussoirs)} gives it that "
                 f"shape; use more voussoirs or thicker rings")
    outline = clean(np.array([*outline_top, inner[-1]]), float(np.ptp(outline_top, axis=0).max()))
    return Ring(polys, outline, (inner[0], outer[0]), (inner[-1], outer[-1]), tuple(ring_of))


def add_arch(
    builder: ModelBuilder,
    shape: ArchShape,
    *,
    voussoirs: int | Sequence[int],
    joints: str = "radial",
    density: float = 2000.0,
    origin: tuple[float, float] = (0.0, 0.0),
    group: str = "voussoir",
    name: str = "voussoir",
    rings: int = 1,
    ring_thicknesses: Sequence[float] | None = None,
    ring_stagger: bool = False,
) -> Assembly:
    """Add the voussoirs of an arch of `shape` (see arch_ring()), its frame's origin at `origin`
    [m]; part "voussoirs", from the left springing, named "<name> 1", "<name> 2", ....
    With rings > 1 (arch_rings()), ring by ring from the intrados, named "ring <i> <name> <k>",
    in groups "<group> ring <i>" (so that a law can be given to the boundary between rings)."""
    cut = arch_ring(shape, voussoirs, joints, origin, rings=rings,
                    ring_thicknesses=ring_thicknesses, ring_stagger=ring_stagger)
    asm = Assembly()
    _add_voussoirs(builder, asm, cut, density, group, name)
    return asm


def _add_voussoirs(builder: ModelBuilder, asm: Assembly, cut: Ring, density: float, group: str,
                   name: str, prefix: str = "") -> None:
    """The voussoirs of `cut` as part "voussoirs" (names and groups: add_arch; `prefix`
    before each name)."""
    numbers = {}
    for poly, ring in zip(cut.voussoirs, cut.rings or [0] * len(cut.voussoirs), strict=True):
        numbers[ring] = numbers.get(ring, 0) + 1
        named = prefix + (f"ring {ring} {name} {numbers[ring]}" if ring
                          else f"{name} {numbers[ring]}")
        asm.add_block(builder, "voussoirs", poly, group=f"{group} ring {ring}" if ring else group,
                      density=density, name=named)


def add_supported_arch(
    builder: ModelBuilder,
    shape: ArchShape,
    *,
    voussoirs: int | Sequence[int],
    joints: str = "radial",
    density: float = 2000.0,
    pier_width: float | None = None,
    pier_height: float | None = None,
    pier_courses: int = 1,
    pier_kind: BodyKind = BodyKind.FIXED,
    origin: tuple[float, float] = (0.0, 0.0),
    group: str = "voussoir",
    rings: int = 1,
    ring_thicknesses: Sequence[float] | None = None,
    ring_stagger: bool = False,
) -> Assembly:
    """An arch (add_arch) on two piers or abutments, on a fixed ground.

    Each pier is pier_width [m] wide (default: the springing face's width plus the ring
    thickness), flush with the intrados below its springing, and pier_height [m] high from
    the ground to the springing (default: pier_width), in `pier_courses` equal blocks of
    kind pier_kind (FIXED: fixed supports; FREE: piers that can rock and slide); the top block
    carries the springing face (a skewback for a segmental arch). The ground (fixed) reaches
    span / 2 beyond the piers so that a collapsing arch falls onto it.
    Parts "ground", "piers" (left pier, then right, bottom up; named "left pier c1", ...),
    "voussoirs"; groups "ground", "pier", `group`. rings, ring_thicknesses, ring_stagger: an
    arch of several rings (arch_rings(); voussoirs' names and groups as add_arch gives them).
    Assembly.joints: "radial", "ring", "support" and "bed" joints (_name_joints).
    """
    cut = arch_ring(shape, voussoirs, joints, origin, rings=rings,
                    ring_thicknesses=ring_thicknesses, ring_stagger=ring_stagger)
    (li, lo), (ri, ro) = cut.left, cut.right
    thickness = max(math.hypot(*(lo - li)), math.hypot(*(ro - ri)))
    if pier_width is None:
        pier_width = max(li[0] - lo[0], ro[0] - ri[0]) + thickness
    pier_height = pier_width if pier_height is None else pier_height
    check_positive(pier_width=pier_width, pier_height=pier_height)
    check_count("pier_courses", pier_courses)
    base = min(li[1], ri[1]) - pier_height
    piers = {
        "left pier": pier_polygons(li[0] - pier_width, li[0], base, li[1], pier_courses,
                                   right_face=(li, lo)),
        "right pier": pier_polygons(ri[0], ri[0] + pier_width, base, ri[1], pier_courses,
                                    left_face=(ri, ro)),
    }
    names = [f"{side} c{c + 1}" for side, polys in piers.items() for c in range(len(polys))]
    check_convex([p for polys in piers.values() for p in polys], names,
                 "check pier_width and pier_height")
    asm = Assembly()
    half = 0.5 * (ri[0] - li[0])
    add_ground(builder, asm, li[0] - pier_width - half, ri[0] + pier_width + half, base,
               pier_width)
    polys = [p for side in piers.values() for p in side]
    for poly, name in zip(polys, names, strict=True):
        asm.add_block(builder, "piers", poly, group="pier", density=density, kind=pier_kind,
                      name=name)
    _add_voussoirs(builder, asm, cut, density, group, "voussoir")
    _name_joints(asm, group)
    return asm


def _name_joints(asm: Assembly, group: str) -> None:
    """Assembly.joints of an arch on piers and the ground: "radial" within a ring (group, or
    "<group> ring <k>"), "ring" between rings, "support" between a voussoir or a pier and the
    piers or the ground, "bed" between the blocks of the piers."""
    rings = [g for g in asm.groups if g == group or g.startswith(f"{group} ring ")]
    for k, ring in enumerate(rings):
        asm.add_joint("radial", ring, ring)
        for other in rings[k + 1:]:
            asm.add_joint("ring", ring, other)
        for support in ("pier", "ground"):
            asm.add_joint("support", ring, support)
    asm.add_joint("bed", "pier", "pier")
    asm.add_joint("support", "pier", "ground")


arch = model_form(
    add_supported_arch, "arch",
    """An arch on its piers and the ground (add_supported_arch; body 0 is the ground, then the
    piers, then the voussoirs from the left), friction mu [-] on every joint.

    >>> model = arch(ArchShape.segmental(span=4.0, rise=1.0, thickness=0.3), voussoirs=9)
    >>> model.body_count
    12
""")
