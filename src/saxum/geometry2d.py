"""Plane geometry of convex polygon blocks: orientation, convexity, area, centroid, inertia.

Formulas: the shoelace sums over the edges of a simple polygon (e.g. Bourke, "Calculating the
area and centroid of a polygon", 1988):
    A   = 1/2 sum (x_i y_i+1 - x_i+1 y_i)
    C   = 1/(6A) sum (p_i + p_i+1)(x_i y_i+1 - x_i+1 y_i)
    J_O = 1/12 sum (x_i y_i+1 - x_i+1 y_i)
              (x_i^2 + x_i x_i+1 + x_i+1^2 + y_i^2 + y_i y_i+1 + y_i+1^2)
and the parallel-axis theorem J_G = J_O - A |C|^2. Multiplied by the density (per unit
thickness, kg/m^2 in 2D, i.e. kg/m^3 times an out-of-plane depth of 1 m) they give mass and
polar moment of inertia.
"""

from dataclasses import dataclass

import numpy as np

from .errors import InputError

__all__ = ["PolygonProperties", "cluster_polygon_properties", "normalize_polygon",
           "polygon_properties"]

_REL_TOL = 1e-12


@dataclass(frozen=True)
class PolygonProperties:
    """Area [m^2], centroid [m] shape (2,), polar second moment of area about it [m^4]."""

    area: float
    centroid: np.ndarray
    polar_moment: float


def _cross_terms(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    w = np.roll(v, -1, axis=0)
    return w, v[:, 0] * w[:, 1] - w[:, 0] * v[:, 1]


def normalize_polygon(vertices, *, name: str = "block") -> np.ndarray:
    """Return the vertices [m] as a float array (n, 2) in counter-clockwise order.

    Raises InputError naming `name` for NaN/inf coordinates, fewer than 3 vertices, repeated or
    collinear vertices, zero area or a non-convex outline.
    """
    v = np.array(vertices, dtype=np.float64)
    if v.ndim != 2 or v.shape[1] != 2:
        raise InputError(f"{name}: vertices must be a list of (x, y) pairs, got shape {v.shape}")
    if len(v) < 3:
        raise InputError(f"{name}: a polygon needs at least 3 vertices, got {len(v)}")
    if not np.all(np.isfinite(v)):
        raise InputError(f"{name}: vertex coordinates contain NaN or infinity")
    _, cross = _cross_terms(v)
    area2 = cross.sum()
    scale = max(float(np.ptp(v[:, 0])), float(np.ptp(v[:, 1])))
    if abs(area2) <= _REL_TOL * scale * scale or scale == 0.0:
        raise InputError(f"{name}: degenerate polygon (zero area); check its vertices")
    if area2 < 0.0:
        v = v[::-1].copy()
    e = np.roll(v, -1, axis=0) - v
    length = np.hypot(e[:, 0], e[:, 1])
    short = np.flatnonzero(length <= _REL_TOL * scale * 1e3)
    if short.size:
        raise InputError(f"{name}: vertices {short[0]} and the next one coincide; remove one")
    turn = e[:, 0] * np.roll(e, -1, axis=0)[:, 1] - e[:, 1] * np.roll(e, -1, axis=0)[:, 0]
    turn /= length * np.roll(length, -1)
    bad = np.flatnonzero(turn <= 1e-9)
    if bad.size:
        k = (bad[0] + 1) % len(v)
        kind = "collinear with its neighbours" if abs(turn[bad[0]]) <= 1e-9 else "a reflex corner"
        raise InputError(
            f"{name}: polygon is not strictly convex: vertex {k} at ({v[k, 0]:g}, "
            f"{v[k, 1]:g}) is {kind}; split the block into convex parts (blocks, or the parts "
            "of one block: ModelBuilder.add_cluster) or remove the vertex"
        )
    return v


def polygon_properties(vertices: np.ndarray) -> PolygonProperties:
    """Area, centroid and polar second moment about the centroid of a CCW polygon (n, 2) [m]."""
    v_in = np.asarray(vertices, dtype=np.float64)
    # Sums are taken about the vertex mean to avoid cancellation for blocks far from the origin.
    origin = v_in.mean(axis=0)
    v = v_in - origin
    w, cross = _cross_terms(v)
    area = 0.5 * cross.sum()
    centroid = ((v + w) * cross[:, None]).sum(axis=0) / (6.0 * area)
    j_origin = (
        cross
        * (
            v[:, 0] ** 2 + v[:, 0] * w[:, 0] + w[:, 0] ** 2
            + v[:, 1] ** 2 + v[:, 1] * w[:, 1] + w[:, 1] ** 2
        )
    ).sum() / 12.0
    polar = j_origin - area * float(centroid @ centroid)
    return PolygonProperties(area=float(area), centroid=centroid + origin,
                             polar_moment=float(polar))


def cluster_polygon_properties(parts: "list[np.ndarray]") -> PolygonProperties:
    """Area, centroid and polar second moment about the centroid of the union of CCW convex
    polygons that do not overlap (a cluster), by the parallel-axis theorem:
    A = sum A_k, C = sum A_k C_k / A, J = sum (J_k + A_k |C_k - C|^2)."""
    if len(parts) == 1:  # the same numbers as for a block
        return polygon_properties(parts[0])
    props = [polygon_properties(part) for part in parts]
    area = sum(p.area for p in props)
    centroid = sum(p.area * p.centroid for p in props) / area
    polar = sum(p.polar_moment + p.area * float((p.centroid - centroid) @ (p.centroid - centroid))
                for p in props)
    return PolygonProperties(area=float(area), centroid=centroid, polar_moment=float(polar))
