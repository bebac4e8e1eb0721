"""Rigid-block limit analysis of a discretized arch under a horizontal load factor, computed
independently of saxum, and the saxum side of the comparison (validation helpers shared by
test_arch_horizontal.py and test_segmental_horizontal.py).

Reference (kinematic theorem of limit analysis for rigid blocks with no tension and no
sliding; J. Heyman, "The safety of masonry arches", Int. J. Mech. Sci. 11, 1969; the
four-hinge mechanism of an arch under horizontal load, e.g. A. Gago, J. Alvarez &
M. Ochsendorf, "Limit analysis of arches under horizontal loads", 2011): for every choice of
four hinges at the joints of the discretized arch (each at the intrados or the extrados end of
its joint), the three moving parts rotate about the first hinge, about the intersection of the
lines through hinges 1-2 and 3-4, and about the last hinge; the virtual power of gravity and
of the horizontal load lambda m g vanishes at
    lambda = sum_k m_k v_y(G_k) / sum_k m_k v_x(G_k),
and a mechanism counts only if every hinge opens the joint on its other end, in the sense of
the motion in which the horizontal load does positive work. The collapse load factor is the
least such lambda (upper-bound theorem: every admissible mechanism gives an upper bound, the
least is the collapse load).
"""

import dataclasses
import itertools
import math

import numpy as np

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value
from saxum.mechanism import mechanism


def area_centroid(p: np.ndarray) -> tuple[float, np.ndarray]:
    """Area [m^2] and centroid [m] of a counter-clockwise polygon (shoelace)."""
    x, y = p[:, 0], p[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * cross.sum()
    return area, np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6 * area)


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _arch_geometry(intrados, extrados, voussoirs: list):
    """Joint ends, joint normals (from voussoir j - 1 into voussoir j), and the voussoirs'
    areas and centroids of an arch (four_hinge_mechanism's arguments)."""
    n = len(voussoirs)
    ends = {"intrados": np.asarray(intrados, float), "extrados": np.asarray(extrados, float)}
    mass, centroid = np.zeros(n), np.zeros((n, 2))
    for k, poly in enumerate(voussoirs):
        mass[k], centroid[k] = area_centroid(np.asarray(poly, float))
    along = ends["extrados"] - ends["intrados"]
    normal = np.column_stack((-along[:, 1], along[:, 0])) / np.hypot(*along.T)[:, None]
    middle = 0.5 * (ends["extrados"] + ends["intrados"])
    ahead = np.vstack((centroid, 2.0 * middle[-1] - centroid[-1]))
    normal *= np.sign(np.einsum("kd,kd->k", normal, ahead - middle))[:, None]
    return ends, normal, mass, centroid


def _velocity(omega, centre, p):
    return omega * np.array([-(p[..., 1] - centre[1]), p[..., 0] - centre[0]]).T


def hinge_factor(geometry, joints, sides, below: float = math.inf):
    """lambda of the four-hinge mechanism with hinges at `joints` (increasing joint
    indices) on `sides` ("intrados" | "extrados") of an arch's _arch_geometry, if it is
    admissible (module doc) and 0 < lambda < below; else None."""
    ends, normal, mass, centroid = geometry
    n = len(mass)
    part = np.searchsorted(np.array(joints), np.arange(n), side="right")
    a, b, c, d = (ends[s][j] for s, j in zip(sides, joints, strict=True))
    # centre of part 2: intersection of lines A-B and D-C
    u, w = b - a, c - d
    den = _cross(u, w)
    if abs(den) < 1e-12:
        return None
    o2 = a + u * _cross(d - a, w) / den
    omega1 = 1.0
    omega2 = omega1 * np.dot(b - a, u) / np.dot(b - o2, u)
    omega3 = omega2 * np.dot(c - o2, w) / np.dot(c - d, w)
    omegas = (0.0, omega1, omega2, omega3, 0.0)
    centres = (a, a, o2, d, d)
    # parts: fixed | 1: voussoirs j0..j1-1 | 2: j1..j2-1 | 3: j2..j3-1 | fixed
    v = np.zeros((n, 2))
    for p in (1, 2, 3):
        rows = part == p
        v[rows] = _velocity(omegas[p], centres[p], centroid[rows])
    work_x = (mass * v[:, 0]).sum()
    if abs(work_x) < 1e-12:
        return None
    lam = (mass * v[:, 1]).sum() / work_x
    if not (0.0 < lam < below):
        return None
    # every hinge opens its joint (the other end of the joint separates) for one sense of
    # the motion, and in that sense the horizontal load does positive work
    opening = []
    for h, (j, side) in enumerate(zip(joints, sides, strict=True)):
        arm = ends["extrados" if side == "intrados" else "intrados"][j] - ends[side][j]
        rel = omegas[h + 1] - omegas[h]  # the part after the joint minus the one before
        opening.append(rel * np.dot(np.array([-arm[1], arm[0]]), normal[j]))
    sense = 1.0 if min(opening) > 0.0 else -1.0 if max(opening) < 0.0 else 0.0
    return lam if sense * work_x > 0.0 else None


def four_hinge_mechanism(intrados: np.ndarray, extrados: np.ndarray, voussoirs: list):
    """(lambda_c, hinges as [(joint, "intrados" | "extrados")]) of the least admissible
    four-hinge mechanism of an arch on fixed supports (module doc).

    intrados, extrados: (n + 1, 2) ends of the joints [m], joint 0 and joint n at the
    springings; voussoirs: the n polygons [m] (uniform density), voussoir k between joints k
    and k + 1."""
    geometry = _arch_geometry(intrados, extrados, voussoirs)
    best = (math.inf, None)
    for joints in itertools.combinations(range(len(voussoirs) + 1), 4):
        for sides in itertools.product(("intrados", "extrados"), repeat=4):
            lam = hinge_factor(geometry, joints, sides, best[0])
            if lam is not None:
                best = (lam, list(zip(joints, sides, strict=True)))
    return best


def semicircular_voussoirs(radius: float, thickness: float, voussoirs: int):
    """(intrados ends, extrados ends, quadrilaterals) of a semicircular arch of mean radius
    `radius` [m] (straight intrados and extrados between the ends of radial joints), joints
    numbered from the right springing."""
    phi = np.pi * np.arange(voussoirs + 1) / voussoirs
    unit = np.column_stack((np.cos(phi), np.sin(phi)))
    inner, outer = (radius - thickness / 2) * unit, (radius + thickness / 2) * unit
    quads = [np.array([inner[k], outer[k], outer[k + 1], inner[k + 1]])
             for k in range(voussoirs)]
    return inner, outer, quads


def semicircular_hinge_factor(radius: float, thickness: float, voussoirs: int, hinges):
    """hinge_factor of a semicircular arch (semicircular_voussoirs) for the hinges
    [(joint, side)] numbered as saxum numbers the voussoirs (from the left springing, as
    semicircular_four_hinge returns them); None if that mechanism is not admissible."""
    geometry = _arch_geometry(*semicircular_voussoirs(radius, thickness, voussoirs))
    mirrored = sorted((voussoirs - j, side) for j, side in hinges)
    return hinge_factor(geometry, [j for j, _ in mirrored], [s for _, s in mirrored])


def semicircular_four_hinge(radius: float, thickness: float, voussoirs: int):
    """four_hinge_mechanism of a semicircular arch of mean radius `radius` [m] (voussoirs with
    straight intrados and extrados between the ends of radial joints), its hinges' joints
    numbered as saxum numbers the voussoirs, from the left springing: joint j at angle
    pi (1 - j / voussoirs) from the right springing (sorted)."""
    inner, outer, quads = semicircular_voussoirs(radius, thickness, voussoirs)
    lam, hinges = four_hinge_mechanism(inner, outer, quads)  # joints from the right here
    return lam, sorted((voussoirs - j, side) for j, side in hinges)


def with_load_factor(model: sx.Model, factor: float, dt: float = 1e-3,
                     direction: tuple[float, ...] | None = None) -> sx.Simulation:
    """A simulation of `model` (2D or 3D) with a constant horizontal inertial load
    factor * g along the unit vector `direction` (default x) on every free block."""
    g = float(np.linalg.norm(model.gravity))
    unit = np.eye(model.dim)[0] if direction is None else np.asarray(direction, float)
    along = tuple((factor * g * unit).tolist())
    loaded = dataclasses.replace(model, accelerations=((lambda t: along),))
    return sx.Simulation(loaded, dt=dt)


def joint_index(joint, voussoirs: int) -> int:
    """Joint index of a mechanism joint of an arch whose voussoirs are named "voussoir 1" ...
    "voussoir n" from joint 0's springing: between voussoir k and k + 1 it is joint k; with a
    support, joint 0 or n."""
    numbers = sorted(int(name.split()[-1]) for name in joint.bodies
                     if name.startswith("voussoir"))
    if len(numbers) == 2:
        return numbers[0]
    return 0 if numbers[0] == 1 else voussoirs


def saxum_horizontal_collapse(model: sx.Model, lam_ref: float, voussoirs: int, side_of):
    """saxum's horizontal collapse load factor of an arch model (bisection from rest to 0.5 %,
    bracket 0.5 to 1.5 lam_ref) and the mechanism of the collapsing case once it has developed
    for 0.05 s, so that every hinge has visibly opened: (factor, mechanism, hinges as sorted
    [(joint, side_of(hinge point))])."""
    result = critical_value(lambda x: with_load_factor(model, x), 0.5 * lam_ref,
                            1.5 * lam_ref, tolerance=0.005,
                            criterion=CollapseCriterion(duration=1.0))
    trial = result.collapse()
    trial.simulation.run(trial.state, 0.05)
    mech = mechanism(trial.simulation.model, trial.state, trial.simulation.integrator.dt)
    found = sorted((joint_index(j, voussoirs), side_of(j.hinge_point)) for j in mech.hinges)
    return result.value, mech, found
