"""Limit analysis of rigid-block models: the largest load factor lambda for which the joints'
forces can balance every free block under dead load + lambda x live load, and the collapse
mechanism, from the same model that saxum runs dynamically.

Static (lower-bound) problem (D. Livesley, "Limit analysis of structures formed from rigid
blocks", Int. J. Numer. Meth. Eng. 12, 1978; M. Gilbert, C. Casapulla & H. M. Ahmed,
"Limit analysis of masonry block structures with non-associative frictional joints using
linear programming", Computers & Structures 84, 2006): the unknowns are the contact forces
R = (R_t, R_n) [N/m; 3D: (R_t, R_n, R_s), N] at the contact points that saxum's detection
finds touching (gap within the detector's closed_gap) at the initial configuration (two
points for two faces in contact in 2D, the corners of the overlap in 3D), and lambda:

    maximise lambda  subject to  sum_alpha H_alpha R_alpha + D + lambda L = 0  (every free
    block: forces and moments about its centre of mass, world frame)
    R_n >= 0 (no tension: with two or more points per joint the resultant stays inside the
    joint, which bounds the eccentricity) and |R_T| <= mu R_n (Coulomb),

D the dead load (weight, constant loads), L the live load (a horizontal acceleration of g on
every free block, or the point loads). In 2D each contact's cone is spanned by two rays, R =
a_1 (n - mu t) + a_2 (n + mu t), a >= 0: a linear programme with bounds only (scipy's HiGHS,
interior point, then crossover to a vertex, whose multipliers are exact; above _LARGE
contact points Clarabel's interior point, eight times faster on a 2000-brick wall, whose
factor is a feasible lower bound within ~1e-7 of the vertex's and whose multipliers are the
centre of the optimal face of mechanisms); in 3D (R_t, R_s,
mu R_n) lies in a second-order cone: a conic programme (Clarabel). Any feasible R is a
statically admissible state, so lambda is a lower bound of the collapse factor of the
associative model; its dual is the kinematic problem, whose solution, the equalities'
multipliers, are virtual velocities u of the blocks with L . u = 1 and lambda = -D . u
(virtual work): the mechanism. With the associative flow rule the relative velocity U of
each contact lies in the dual cone, U_n >= mu |U_T| (a sliding joint dilates): that is the
price of a convex problem. For purely rotational mechanisms (hinges, no sliding) the
associative and the true (non-associative) factors coincide; where sliding takes part the
associative factor is only an upper estimate (Radenkovic's theorems: the true collapse
factor lies between the frictionless one and the associative one).
Settlements (live="settlement"): no live load (lambda = 0); supports move at given velocities
U_s, and the programme minimises the power of the contact forces on them, sum R . c with c
the contacts' relative velocities due to the supports' motion alone: among the admissible
states, the one that the imposed motion selects (the maximum work of the reactions on it,
Drucker's principle; an arch on spreading supports takes its minimum thrust). The dual's
multipliers are then velocities u of the free blocks with U = E^T u + c in the dilatancy
cones, and the dead load's power D . u equals the power on the supports. Water
(live="water"): the model's field loads (a flood's pressures at the initial configuration)
times lambda.
`friction="non-associative"` follows the iterative scheme of Gilbert, Casapulla & Ahmed
(2006) in a simplified form: from the associative solution on, each programme fixes the
friction limit of every contact at mu R_n of the previous solution, |R_T| <= mu R_n^(k-1)
(a limit independent of the current normal force, whose flow rule has no dilatancy), until
the factor (with settlements: the power on the supports) repeats while the previous forces
satisfy Coulomb with their own normal forces:
those forces are then optimal for the last programme, and with its multipliers they make a
state that is in equilibrium, within the Coulomb cones and has a non-dilatant mechanism
sliding where the friction is spent: a collapse state of the non-associative model, its
factor at most the associative one (which bounds every Coulomb-admissible state). It is not
proven the least such state (non-associative collapse loads need not be unique); an
iteration whose factor keeps changing is reported, not hidden.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from .contacts import Contacts
from .detection import DetectionSettings
from .detection.detector import detector_for
from .errors import InputError
from .mechanism import Joint, Mechanism, _line_of, joint_index, joint_resultants, wall_frame
from .model import BodyKind, Model

__all__ = ["LimitAnalysis", "limit_analysis", "rest_certificate", "scenario_limit_analysis",
           "stands", "static_critical_value"]

_STATIONARY = 1e-6
"""A contact point whose relative virtual velocity is below this, relative to the fastest
block point's speed, does not move (the multipliers at a vertex are exact to ~1e-12; a
conic solver's to its tolerance ~1e-8)."""
_FEASIBLE = 1e-9
"""HiGHS's primal and dual feasibility tolerances on the scaled programme (forces in units
of the largest load) [-]: lambda to about this, relative."""
_LARGE = 4000
"""A 2D associative programme with more contact points than this is solved by Clarabel
(_solve_rays_conic), a smaller one by HiGHS (a vertex)."""
_REPEAT = 1e-9
"""The non-associative iteration stops when lambda repeats to this, relative, and the
forces satisfy Coulomb's |R_T| <= mu R_n with their own normal forces to this (in units of
the largest load) [-]."""
_ITERATIONS = 50
"""The non-associative iteration gives up (and says so) after this many programmes."""


@dataclass
class LimitAnalysis:
    """The result of a limit analysis: the load factor lambda [-] (collapse under dead +
    lambda live load), the contacts used (initial configuration) with their forces at
    collapse in the local frames (force, (contacts, dim) [N/m; 3D: N]), the blocks' virtual
    velocities (velocity, (bodies, dof) [m/s, rad/s], world frame, normalised so that the
    fastest block point moves at 1 m/s; 0 for supports), the relative velocity of each
    contact in its local frame (relative, (contacts, dim)), the mechanism, how friction was
    treated ("associative" or "non-associative") and the number of programmes solved.
    Settlement (live "settlement"): no load factor (factor nan); support_power [W/m; 3D: W]
    the power of the structure's forces on the moving supports at their given velocities
    (one support moving at 1 m/s: the force on it along its motion, N/m), the least over
    the admissible states (the thrust of an arch on spreading supports, module doc)."""

    factor: float
    model: Model = field(repr=False)
    contacts: Contacts = field(repr=False)
    force: np.ndarray = field(repr=False)
    velocity: np.ndarray = field(repr=False)
    relative: np.ndarray = field(repr=False)
    mechanism: Mechanism = field(repr=False)
    friction: str = "associative"
    iterations: int = 1
    live: str = "horizontal"
    support_power: float | None = None

    def contact_dict(self) -> dict:
        """The contacts with their forces at collapse, as saxum.mechanism's functions read
        them (candidate, antagonist, point, frame, gap, force)."""
        k = self.contacts.count
        c = self.contacts
        return {"candidate": c.candidate[:k], "antagonist": c.antagonist[:k],
                "point": c.point[:k], "frame": c.frame[:k], "gap": c.gap[:k],
                "force": self.force}

    def thrust_line(self, centre: tuple[float, float]) -> np.ndarray:
        """2D: the joints' centres of pressure at collapse [m], ordered about `centre` [m]
        (saxum.mechanism.thrust_line): the thrust line of an arch."""
        from .mechanism import thrust_line

        return thrust_line(self.contact_dict(), math.inf, centre)

    def heading(self) -> str:
        """The result in a few words, for a picture's title."""
        if self.live == "settlement":
            unit = "W/m" if self.model.dim == 2 else "W"
            return f"settled supports, least power on them {self.support_power:.5g} {unit}"
        return f"limit load factor {self.factor:.5g}"

    def text(self) -> str:
        """The factor and the mechanism in words."""
        what = {"horizontal": "horizontal acceleration lambda g",
                "forces": "point loads x lambda",
                "water": "water pressure x lambda"}.get(self.live, "live load x lambda")
        moving = self.mechanism.moving
        iterations = (f", {self.iterations} programmes" if self.friction == "non-associative"
                      else "")
        how = f"{self.friction} friction{iterations}; {self.contacts.count} contact points"
        unit = "W/m" if self.model.dim == 2 else "W"
        head = (f"settled supports: the structure's forces on them do {self.support_power:.6g}"
                f" {unit} at their velocities, the least of the admissible states ({how})"
                if self.live == "settlement" else
                f"limit load factor lambda = {self.factor:.6g} ({what}; {how})")
        return (head + "\n"
                "mechanism (virtual velocities, the fastest block point at 1 m/s):\n"
                + "\n".join([f"moving blocks ({len(moving)}): " + ", ".join(moving),
                             *self.mechanism.text().splitlines()[1:]]))


def limit_analysis(model: Model, *, live: str | np.ndarray = "horizontal",
                   direction: float | tuple[float, ...] = 1.0,
                   friction: str = "associative",
                   detection: DetectionSettings | None = None,
                   settlement: Mapping[str, Sequence[float]] | None = None) -> LimitAnalysis:
    """The limit load factor of `model` (rigid blocks, 2D or 3D; module doc).

    live: "horizontal" (an acceleration lambda g along `direction` on every free block: a
    sign along x, or in 3D a horizontal vector), "forces"
    (the model's point loads times lambda, the rest dead), "water" (the model's field
    loads, the water of a flood, times lambda: a factor on the water's unit weight rho_w g),
    "settlement" (no live load: supports moving at the generalized velocities
    `settlement`, {fixed block name: (v_x, v_y, omega) [m/s, rad/s]; 3D: (v_x, v_y, v_z,
    omega_x, omega_y, omega_z)}; the state of least power on them, module doc) or an array
    (bodies, dof) [N/m, N m/m; 3D: N, N m] of generalized forces in the world frame. Dead
    load: gravity and the model's constant loads at t = 0 (uniform accelerations, point
    loads unless live, field loads such as water at the initial configuration unless live).
    friction: "associative" or "non-associative" (module doc). Raises InputError for a
    model it cannot analyse (a free block that touches nothing, a dead load that no forces
    balance, a live load that cannot cause collapse)."""
    if friction not in ("associative", "non-associative"):
        raise InputError(f"friction must be \"associative\" or \"non-associative\", got "
                         f"{friction!r}")
    settling = isinstance(live, str) and live == "settlement"
    if settling != (settlement is not None) or settlement == {}:
        raise InputError("a settlement analysis takes live=\"settlement\" and the supports' "
                         "velocities, settlement={fixed block name: generalized velocity}; "
                         "give both or neither")
    if model.fe is not None or (model.body_kind == BodyKind.DEFORMABLE).any():
        raise InputError("limit analysis is for rigid blocks: this model has deformable "
                         "blocks; give them no material to make them rigid")
    free = np.flatnonzero(model.body_kind == BodyKind.FREE)
    if free.size == 0:
        raise InputError("limit analysis needs at least one free block")
    contacts = _touching(model, detection)
    dead, load, label = _loads(model, live, direction)
    _check_touching(model, contacts, free)
    k, dim = contacts.count, model.dim
    mu = model.law_friction[contacts.law[:k]]
    moved, support = _supports(model, settlement)
    power = [e.T @ support[moved].ravel() for e in _unit_forces(model, contacts, moved)]
    solve = functools.partial(_solve_2d if dim == 2 else _solve_3d,
                              power=power if settlement is not None else None)
    unit, rhs, lhs, row, f0 = _scaled(model, _unit_forces(model, contacts, free),
                                      -dead[free].ravel(),
                                      None if settlement is not None else load[free].ravel())
    try:
        force, u, lam = solve(unit, mu, rhs, lhs, None)
    except _Infeasible:
        raise _dead_load_error(model, free, unit, mu, rhs, solve) from None
    except _Unbounded:
        if settlement is not None:
            raise InputError(f"the supports' motion ({_names(model, moved)}) finds no bound: "
                             "the blocks can press on them with forces as large as any (an "
                             "unbounded thrust, e.g. a wedge between closing supports); give "
                             "them a motion that the structure resists finitely") from None
        loaded = free[np.abs(load[free]).max(axis=1) > 0.0]
        raise InputError(f"the live load ({label}) cannot cause collapse: the joints carry it "
                         f"at any factor (an unbounded factor); it acts on "
                         f"{_names(model, loaded)}") from None
    if lam < 0.0 and settlement is None:
        raise InputError(f"the structure cannot stand under its dead load alone: it needs "
                         f"the live load ({label}) reversed, lambda = {lam:.6g} < 0, to "
                         "stand; reverse the live load's direction or check the model")
    iterations = 1
    if friction == "non-associative":
        for iterations in range(2, _ITERATIONS + 1):  # noqa: B007 (reported after the loop)
            # The last forces satisfy this programme's limits exactly when they satisfy
            # Coulomb with their own normal forces; then, if they reach its optimum, they are
            # an optimum of it, with its multipliers a non-dilatant mechanism (module doc)
            last, admissible = (lam, force), (np.linalg.norm(np.delete(force, 1, axis=1),
                                                             axis=1)
                                              - mu * force[:, 1]).max() <= _REPEAT
            force, u, lam = solve(unit, mu, rhs, lhs, mu * force[:, 1])
            if admissible and abs(lam - last[0]) <= _REPEAT * abs(last[0]):
                lam, force = last
                break
        else:
            raise InputError(f"the non-associative iteration did not settle in {_ITERATIONS} "
                             f"programmes (the factor still changes, the last "
                             f"{lam:.6g}): use friction=\"associative\" for an upper estimate")
    force *= f0
    velocity = support.copy()
    velocity[free] = (row * u).reshape(free.size, model.dof)
    speed = np.linalg.norm(velocity[:, :dim], axis=1) + np.linalg.norm(
        velocity[:, dim:], axis=1) * model.body_radius
    velocity /= speed.max()
    both = np.concatenate((free, moved))
    relative = np.stack([e.T @ velocity[both].ravel()
                         for e in _unit_forces(model, contacts, both)], axis=1)
    mech = _mechanism(model, contacts, force, relative, velocity, mu)
    if settlement is None:
        return LimitAnalysis(lam, model, contacts, force, velocity, relative, mech, friction,
                             iterations, label)
    return LimitAnalysis(math.nan, model, contacts, force, velocity, relative, mech, friction,
                         iterations, "settlement", lam * f0)


def scenario_limit_analysis(path, *, overrides: tuple[str, ...] = (),
                            live: str = "horizontal",
                            friction: str = "associative") -> LimitAnalysis:
    """limit_analysis of the scenario file at `path` (keys overridden by `overrides`,
    "key=value"). live "horizontal": the horizontal acceleration lambda g along the sign of
    loads.horizontal_acceleration (+x if 0; 3D: at loads.horizontal_azimuth), which is taken
    out of the dead load; "forces": the point loads ([[loads.point_loads]]) times lambda;
    "water": the flood's pressures ([loads.flood]) times lambda; "settlement": the supports
    of [[loads.settlements]] moving at their mean velocities (magnitude / time along
    direction, rotation / time), the state of least power on them."""
    from .scenario import _unit, load_scenario

    scenario = load_scenario(path, list(overrides))
    loads = scenario.loads
    if loads.ground_motion is not None or (loads.settlements and live != "settlement"):
        raise InputError(f"{path}: limit analysis takes constant loads; this scenario has "
                         "a ground motion or settlements: leave them out (--unset), or "
                         "analyse the settlements with --live settlement")
    if live == "settlement" and not loads.settlements:
        raise InputError(f"{path}: --live settlement moves the supports of "
                         "[[loads.settlements]], and this scenario has none")
    if live == "water" and loads.flood is None:
        raise InputError(f"{path}: --live water multiplies the water of [loads.flood], and "
                         "this scenario has none")
    model = scenario.build_model()  # checks the settlements' keys
    dim, settlement = model.dim, None
    if live == "settlement":
        down = -np.eye(dim)[-1]
        turning = np.zeros(model.dof - dim)
        settlement = {s.block: np.r_[s.magnitude / s.time * _unit(
            s.direction or down, f"settlements[{k}].direction", dim),
            (turning + np.asarray(s.rotation, dtype=np.float64)) / s.time]
            for k, s in enumerate(loads.settlements)}
    if loads.load_factor_rate != 0.0:
        raise InputError(f"{path}: loads.load_factor_rate is a dynamic ramp; limit analysis "
                         "finds the factor directly: set it to 0")
    direction: float | tuple[float, ...] = 1.0
    if live == "horizontal":
        sign = -1.0 if loads.horizontal_acceleration < 0.0 else 1.0
        if scenario.structure.dim == 3:
            phi = math.radians(loads.horizontal_azimuth)
            direction = (sign * math.cos(phi), sign * math.sin(phi), 0.0)
        else:
            direction = sign
        scenario = load_scenario(path, [*overrides, "loads.horizontal_acceleration=0.0"])
    elif live == "forces" and not loads.point_loads:
        raise InputError(f"{path}: --live forces multiplies the point loads, and this "
                         "scenario has none ([[loads.point_loads]])")
    d = scenario.detection
    if live == "horizontal":
        model = scenario.build_model()
    return limit_analysis(model, live=live, direction=direction,
                          friction=friction, settlement=settlement,
                          detection=DetectionSettings(alert=d.alert, margin=d.margin,
                                                      per_pair=d.per_pair))


def stands(model: Model, *, detection: DetectionSettings | None = None) -> bool:
    """Whether contact forces in the Coulomb cones of the touching contacts balance every
    free block under all of `model`'s loads at t = 0 (the programme with lambda = 0):
    the static verdict on a structure."""
    free = np.flatnonzero(model.body_kind == BodyKind.FREE)
    contacts = _touching(model, detection)
    _check_touching(model, contacts, free)
    dead, _, _ = _loads(model, "horizontal", 1.0)
    unit, rhs, _, _, _ = _scaled(model, _unit_forces(model, contacts, free),
                                 -dead[free].ravel(), None)
    solve = _solve_2d if model.dim == 2 else _solve_3d
    try:
        solve(unit, model.law_friction[contacts.law[:contacts.count]], rhs, None, None)
    except _Infeasible:
        return False
    return True


def static_critical_value(path, key: str, stands_at: float, collapses_at: float, *,
                          overrides: tuple[str, ...] = (),
                          tolerance: float = 1e-6) -> float:
    """The critical value of the scenario key `key` [its unit] by the static verdict
    (stands()): loads.horizontal_acceleration directly from the limit factor (a = lambda
    |g|), any other key (a thickness, a friction coefficient, a point load) by bisection
    between a value where the structure stands and one where it does not, to `tolerance`
    relative. Constant loads only (no ground motion or settlements)."""
    from .scenario import load_scenario

    scenario = load_scenario(path, list(overrides))
    if scenario.loads.ground_motion is not None or scenario.loads.settlements:
        raise InputError(f"{path}: the static analysis takes constant loads; a ground motion "
                         "or a settlement has no static critical value")
    if key == "loads.horizontal_acceleration":
        sign = math.copysign(1.0, collapses_at)
        result = scenario_limit_analysis(path, overrides=(
            *overrides, f"loads.horizontal_acceleration={sign!r}"))
        g = float(np.linalg.norm(scenario.loads.gravity_for(scenario.structure.dim)))
        return sign * result.factor * g

    def standing(x: float) -> bool:
        s = load_scenario(path, [*overrides, f"{key}={x!r}"])
        return stands(s.build_model(), detection=DetectionSettings(
            alert=s.detection.alert, margin=s.detection.margin, per_pair=s.detection.per_pair))

    from .collapse import bisect

    return 0.5 * sum(bisect(lambda x: not standing(x), stands_at, collapses_at, tolerance))


def rest_certificate(problem, v_free: np.ndarray) -> bool:
    """Whether the last step's contact problem (saxum.solver.ContactProblem, rigid blocks) has
    a rest solution: impulses in the Coulomb cones of its closed contacts that bring every
    free block to rest, H R = M (V - v_free) (saxum.solver.equilibrium, whose rest
    hypothesis picks the closed contacts and the loads), found by the programme of this
    module with lambda = 0. It certifies that the structure can stand where it is under the
    step's loads (an equilibrium to the programme's tolerance, 1e-9 of the loads)."""
    from .solver.equilibrium import rest_hypothesis

    hypothesis = rest_hypothesis(problem, v_free)
    if hypothesis is None:
        return False
    closed, slot, force = hypothesis
    model = problem.model
    dof = model.dof
    if not np.any(force):
        return True
    c = problem.contacts
    nfree = len(force)
    unit = []
    for r in range(model.dim):
        rows, cols, vals = [], [], []
        for body, h in ((c.candidate[closed], problem.h_cand), (c.antagonist[closed],
                                                                 problem.h_ant)):
            on = np.flatnonzero(slot[body] >= 0)
            rows.append((slot[body[on]][:, None] * dof + np.arange(dof)[None, :]).ravel())
            cols.append(np.repeat(on, dof))
            vals.append(h[closed[on], r, :].ravel())
        unit.append(sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                          np.concatenate(cols))),
                                  shape=(nfree * dof, closed.size)))
    unit, rhs, _, _, _ = _scaled(model, unit, force.ravel(), None)
    solve = _solve_2d if model.dim == 2 else _solve_3d
    try:
        solve(unit, problem.friction[closed], rhs, None, None)
    except InputError:  # infeasible, or no solution found: no certificate either way
        return False
    return True


def _scaled(model: Model, unit: list, rhs: np.ndarray, load: np.ndarray | None):
    """The programme scaled to entries of order one (HiGHS's feasibility tolerances are
    absolute): forces in units of the largest load F0, moment rows over the smallest free
    block size L0. Returns the scaled unit matrices, rhs and load, the row scale and F0."""
    free = model.body_kind == BodyKind.FREE
    f0 = float(max(np.abs(rhs).max(), 0.0 if load is None else np.abs(load).max()))
    l0 = float(model.body_size[free].min())
    d = model.dim
    row = np.tile(np.r_[np.ones(d), np.full(model.dof - d, 1.0 / l0)], int(free.sum()))
    return ([sp.diags(row) @ e for e in unit], row * rhs / f0,
            None if load is None else row * load / f0, row, f0)


def _touching(model: Model, detection: DetectionSettings | None) -> Contacts:
    """The contacts detected at the initial configuration whose gap is within the
    detector's closed_gap (touching), between a free block and another body."""
    detector = detector_for(model, detection)
    found = detector.contacts_at(model.body_q0)
    n = found.count
    free = model.body_kind == BodyKind.FREE
    keep = np.flatnonzero((found.gap[:n] <= detector.closed_gap)
                          & (free[found.candidate[:n]] | free[found.antagonist[:n]]))
    out = Contacts(model.dim, max(keep.size, 1))
    out.count = keep.size
    for name in Contacts._fields():
        getattr(out, name)[: keep.size] = getattr(found, name)[keep]
    return out


def _names(model: Model, bodies, most: int = 8) -> str:
    bodies = list(bodies)
    text = ", ".join(model.body_name[b] for b in bodies[:most])
    return text + (f" and {len(bodies) - most} more" if len(bodies) > most else "")


def _check_touching(model: Model, contacts: Contacts, free: np.ndarray) -> None:
    k = contacts.count
    touched = np.zeros(model.body_count, dtype=bool)
    touched[contacts.candidate[:k]] = touched[contacts.antagonist[:k]] = True
    alone = free[~touched[free]]
    if alone.size:
        raise InputError(f"free block(s) touching nothing at the start: {_names(model, alone)}; "
                         "a block must rest on another (gap within the detector's closed gap) "
                         "for its weight to be carried: move it into contact or make it fixed")


def _supports(model: Model, settlement: Mapping[str, Sequence[float]] | None
              ) -> tuple[np.ndarray, np.ndarray]:
    """The moving supports' body indices and the generalized velocities (bodies, dof) [m/s,
    rad/s] of all bodies that `settlement` ({fixed block name: velocity}) gives them (0
    elsewhere)."""
    velocity = np.zeros((model.body_count, model.dof))
    moved = []
    for name, v in (settlement or {}).items():
        if name not in model.body_name:
            raise InputError(f"settlement: no block called {name!r}; give a fixed block "
                             "(a support) by its name")
        b = model.body_name.index(name)
        if model.body_kind[b] == BodyKind.FREE:
            raise InputError(f"settlement: {name!r} is a free block; only a fixed block (a "
                             "support) has an imposed motion")
        v = np.asarray(v, dtype=np.float64)
        if v.shape != (model.dof,) or not np.all(np.isfinite(v)):
            raise InputError(f"settlement: the velocity of {name!r} must be {model.dof} finite "
                             f"numbers (translation [m/s], then rotation [rad/s]), got {v}")
        velocity[b] = v
        moved.append(b)
    return np.array(moved, dtype=np.int64), velocity


def _loads(model: Model, live, direction) -> tuple[np.ndarray, np.ndarray, str]:
    """(dead, live) generalized forces (bodies, dof) [N/m, N m/m; 3D: N, N m] in the world
    frame (moments about the centres of mass), and the live load's label."""
    n, d, dof = model.body_count, model.dim, model.dof
    free = model.body_kind == BodyKind.FREE
    mass = np.where(free, model.body_mass, 0.0)
    dead = np.zeros((n, dof))
    dead[:, :d] = mass[:, None] * model.gravity[None, :]
    for acc in model.accelerations:
        dead[:, :d] += mass[:, None] * np.asarray(acc(0.0), dtype=np.float64)[None, :d]
    forces = np.zeros((n, dof))
    for bodies, force in model.forces:
        np.add.at(forces, bodies, np.asarray(force(0.0), dtype=np.float64))
    water = np.zeros((n, dof))
    for load in model.field_loads:
        load.add(model, model.body_q0, 0.0, water)
    if isinstance(live, str) and live == "water":
        if not np.any(water[free]):
            raise InputError("live=\"water\" multiplies the model's water loads (a flood), "
                             "and it has none on its free blocks")
        return dead + forces, water, "water"
    dead += water
    if isinstance(live, str) and live == "settlement":
        return dead + forces, np.zeros((n, dof)), "settlement"
    if isinstance(live, str) and live == "horizontal":
        h = np.zeros(d)
        if np.ndim(direction) == 0:
            h[0] = math.copysign(1.0, float(direction))
        else:
            h[:] = np.asarray(direction, dtype=np.float64)
            if abs(h[-1]) > 1e-12 * np.linalg.norm(h) or not np.linalg.norm(h) > 0.0:
                raise InputError(f"direction of the horizontal live load must be a nonzero "
                                 f"horizontal vector, got {tuple(h)}")
            h /= np.linalg.norm(h)
        g = float(np.linalg.norm(model.gravity))
        load = np.zeros((n, dof))
        load[:, :d] = mass[:, None] * g * h[None, :]
        return dead + forces, load, "horizontal"
    if isinstance(live, str) and live == "forces":
        if not np.any(forces[free]):
            raise InputError("live=\"forces\" multiplies the model's point loads on free "
                             "blocks, and it has none")
        return dead, forces, "forces"
    if isinstance(live, str):
        raise InputError(f"live must be \"horizontal\", \"forces\", \"water\", "
                         f"\"settlement\" or an array (bodies, dof), got {live!r}")
    load = np.asarray(live, dtype=np.float64)
    if load.shape != (n, dof) or not np.all(np.isfinite(load)):
        raise InputError(f"a live load array must be finite, of shape ({n}, {dof}) (bodies, "
                         f"dof), got shape {load.shape}")
    return dead + forces, load, "array"


def _unit_forces(model: Model, contacts: Contacts, free: np.ndarray) -> list[sp.csc_matrix]:
    """For each local direction r (t, n; 3D t, n, s): the sparse matrix (blocks `free` x
    dof, contacts) of the generalized forces [N, N m] on those blocks of a unit force along
    the contact's r-th frame row: +f at the point on the candidate, -f on the antagonist at
    the antagonist's point (point - gap n), moments about the centres of mass. Its transpose
    takes the blocks' velocities to the contacts' relative velocities."""
    k, d, dof = contacts.count, model.dim, model.dof
    slot = np.full(model.body_count, -1)
    slot[free] = np.arange(free.size)
    cand, ant = contacts.candidate[:k], contacts.antagonist[:k]
    point, frame = contacts.point[:k], contacts.frame[:k]
    other = point - contacts.gap[:k, None] * frame[:, 1]
    out = []
    for r in range(d):
        f = frame[:, r]
        rows, cols, vals = [], [], []
        for body, p, sign in ((cand, point, 1.0), (ant, other, -1.0)):
            arm = p - model.body_q0[body, :d]
            if d == 2:
                moment = (arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0])[:, None]
            else:
                moment = np.cross(arm, f)
            gen = sign * np.hstack((f, moment))
            on = slot[body] >= 0
            idx = np.flatnonzero(on)
            rows.append((slot[body[idx]][:, None] * dof + np.arange(dof)[None, :]).ravel())
            cols.append(np.repeat(idx, dof))
            vals.append(gen[idx].ravel())
        out.append(sp.csc_matrix((np.concatenate(vals), (np.concatenate(rows),
                                                         np.concatenate(cols))),
                                 shape=(free.size * dof, k)))
    return out


def _solve_2d(unit, mu, rhs, load, limit, power=None):
    """The 2D programme (module doc) with HiGHS: associative (limit None: the two rays of
    each cone) or with fixed friction limits |R_t| <= limit [N/m]. Returns the contact forces
    (k, 2) (t, n), the free blocks' virtual velocities (L . u = 1) and lambda. With `power`
    (the relative velocities (t, n) [m/s] that the moving supports give the contacts, each
    (k,)), lambda = 0 and the forces minimise the power on the supports, sum R . power,
    which is returned instead of lambda; the velocities then make U = E^T u + power
    admissible."""
    from scipy.optimize import linprog

    e_t, e_n = unit
    k = e_t.shape[1]
    fixed = load is None  # a feasibility problem: lambda = 0
    load = np.zeros(e_t.shape[0]) if fixed else load
    cost = np.zeros(2 * k + 1)
    if limit is None:
        a_eq = sp.hstack((e_n - e_t @ sp.diags(mu), e_n + e_t @ sp.diags(mu),
                          sp.csc_matrix(load[:, None])), format="csc")
        bounds = np.zeros((2 * k + 1, 2))
        bounds[:k, 1] = np.inf
        if power is not None:  # R = a_1 (n - mu t) + a_2 (n + mu t)
            cost[:2 * k] = np.r_[power[1] - mu * power[0], power[1] + mu * power[0]]
    else:
        a_eq = sp.hstack((e_t, e_n, sp.csc_matrix(load[:, None])), format="csc")
        bounds = np.zeros((2 * k + 1, 2))
        bounds[:k, 0], bounds[:k, 1] = -limit, limit
        if power is not None:
            cost[:2 * k] = np.r_[power[0], power[1]]
    bounds[k:2 * k, 1] = np.inf
    bounds[-1] = (0.0, 0.0) if fixed else (-np.inf, np.inf)
    if power is None:
        cost[-1] = -1.0
    if k > _LARGE and limit is None and not fixed:
        x, u = _solve_rays_conic(a_eq, rhs, cost)
    else:
        res = linprog(cost, A_eq=a_eq, b_eq=rhs, bounds=bounds, method="highs-ipm",
                      options={"primal_feasibility_tolerance": _FEASIBLE,
                               "dual_feasibility_tolerance": _FEASIBLE})
        _check_status(res.status, res.message)
        x, u = res.x, -res.eqlin.marginals
    if limit is None:
        force = np.column_stack((mu * (x[k:2 * k] - x[:k]), x[:k] + x[k:2 * k]))
    else:
        force = np.column_stack((x[:k], x[k:2 * k]))
    return force, u, float(x[-1] if power is None else cost @ x)


def _solve_rays_conic(a_eq, rhs, cost):
    """The associative 2D programme (rays a >= 0, lambda free, the last variable) with
    Clarabel's interior point method, for large programmes (_LARGE): its direct
    factorisation is about 8 times faster than HiGHS's interior point (whose iterative
    linear solves dominate on a wall) and its optimum is primal feasible (a lower bound, to
    round-off), the factor within ~1e-7 of the vertex's; but its multipliers are the
    centre of the optimal face, not a vertex (module doc). Returns (x, u) as _solve_2d's
    solution and virtual velocities."""
    import clarabel

    m, n = a_eq.shape
    a = sp.vstack((a_eq, -sp.eye(n - 1, n, format="csc")), format="csc")
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    # tighter than the defaults: with the default regularisation (1e-8) the factor of a
    # 2000-brick wall came 1.8e-6 low, with these 4e-8 (benchmarks/limit.py)
    settings.tol_gap_abs = settings.tol_gap_rel = settings.tol_feas = 1e-11
    settings.static_regularization_constant = 1e-12
    sol = clarabel.DefaultSolver(sp.csc_matrix((n, n)), cost, a,
                                 np.concatenate((rhs, np.zeros(n - 1))),
                                 [clarabel.ZeroConeT(m), clarabel.NonnegativeConeT(n - 1)],
                                 settings).solve()
    _check_conic(str(sol.status))
    return np.asarray(sol.x), np.asarray(sol.z)[:m]


def _solve_3d(unit, mu, rhs, load, limit, power=None):
    """The 3D programme with Clarabel: (mu R_n, R_t, R_s) in a second-order cone per contact
    (associative; limit None), or R_n >= 0 and |(R_t, R_s)| <= limit. Returns as _solve_2d
    (power: as there, (t, n, s))."""
    import clarabel

    e_t, e_n, e_s = unit
    k = e_t.shape[1]
    fixed = load is None  # a feasibility problem: lambda = 0 (one more equation)
    if fixed:
        e_t, e_n, e_s = (sp.vstack((e, sp.csc_matrix((1, k))), format="csc") for e in unit)
        load, rhs = np.r_[np.zeros(e_t.shape[0] - 1), 1.0], np.r_[rhs, 0.0]
    m = e_t.shape[0]
    # variables: (R_t, R_n, R_s) per contact, interleaved, then lambda
    g = sp.hstack((e_t, e_n, e_s), format="csc")
    order = np.concatenate([np.arange(k) + j * k for j in range(3)]).reshape(3, k).T.ravel()
    g = g[:, order]
    a_eq = sp.hstack((g, sp.csc_matrix(load[:, None])), format="csc")
    ids = np.arange(k)
    if limit is None:
        # s = (mu R_n, R_t, R_s) = -A x
        rows = np.concatenate((3 * ids, 3 * ids + 1, 3 * ids + 2))
        cols = np.concatenate((3 * ids + 1, 3 * ids, 3 * ids + 2))
        vals = -np.concatenate((mu, np.ones(k), np.ones(k)))
        cone_a = sp.csc_matrix((vals, (rows, cols)), shape=(3 * k, 3 * k + 1))
        cone_b = np.zeros(3 * k)
        cones = [clarabel.ZeroConeT(m)] + [clarabel.SecondOrderConeT(3)] * k
    else:
        # R_n >= 0 (nonnegative cone), then (limit, R_t, R_s) in a second-order cone
        n_rows = sp.csc_matrix((-np.ones(k), (ids, 3 * ids + 1)), shape=(k, 3 * k + 1))
        rows = np.concatenate((3 * ids + 1, 3 * ids + 2))
        cols = np.concatenate((3 * ids, 3 * ids + 2))
        soc = sp.csc_matrix((-np.ones(2 * k), (rows, cols)), shape=(3 * k, 3 * k + 1))
        cone_a = sp.vstack((n_rows, soc), format="csc")
        cone_b = np.concatenate((np.zeros(k), np.column_stack(
            (limit, np.zeros(k), np.zeros(k))).ravel()))
        cones = ([clarabel.ZeroConeT(m), clarabel.NonnegativeConeT(k)]
                 + [clarabel.SecondOrderConeT(3)] * k)
    a = sp.vstack((a_eq, cone_a), format="csc")
    b = np.concatenate((rhs, cone_b))
    q = np.zeros(3 * k + 1)
    if power is None:
        q[-1] = -1.0
    else:
        q[:-1] = np.column_stack(power).ravel()
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-10
    settings.tol_feas = 1e-10
    solver = clarabel.DefaultSolver(sp.csc_matrix((3 * k + 1, 3 * k + 1)), q, a, b, cones,
                                    settings)
    sol = solver.solve()
    _check_conic(str(sol.status))
    x = np.asarray(sol.x)
    force = x[:-1].reshape(k, 3)
    return force, np.asarray(sol.z)[:m - fixed], float(x[-1] if power is None else q @ x)


def _check_status(status: int, message: str) -> None:
    """Turn an infeasible or unbounded programme into the exception that _diagnose words."""
    if status == 2:
        raise _Infeasible(message)
    if status == 3:
        raise _Unbounded(message)
    if status != 0:
        raise InputError(f"the linear programme (HiGHS) stopped without a solution: {message}")


def _check_conic(status: str) -> None:
    """As _check_status for Clarabel's status: dual infeasible is an unbounded factor."""
    if "Infeasible" in status:
        _check_status(3 if "Dual" in status else 2, status)
    if "Solved" not in status:
        raise InputError(f"the conic solver (Clarabel) stopped without a solution: {status}")


class _Infeasible(InputError):
    pass


class _Unbounded(InputError):
    pass


def _dead_load_error(model: Model, free: np.ndarray, unit, mu, rhs, solve) -> InputError:
    """The error for a dead load that no contact forces balance, naming the blocks that stay
    out of balance in the least-squares-free sense of the phase-one programme: with a slack
    s+ - s- added to every equation and their sum minimised, the blocks whose rows keep
    slack cannot be balanced (module doc)."""
    from scipy.optimize import linprog

    e_t, e_n = unit[0], unit[1]
    m, k = e_t.shape
    # 2D rays, or in 3D the four rays of the inscribed friction pyramid: enough to say which
    # blocks fall (a block that falls with it fails with the cone as well, to round-off)
    cols = [e_n - e_t @ sp.diags(mu), e_n + e_t @ sp.diags(mu)]
    if len(unit) == 3:
        cols += [e_n - unit[2] @ sp.diags(mu), e_n + unit[2] @ sp.diags(mu)]
    eye = sp.identity(m, format="csc")
    a_eq = sp.hstack([*cols, eye, -eye], format="csc")
    cost = np.concatenate((np.zeros(len(cols) * k), np.ones(2 * m)))
    res = linprog(cost, A_eq=a_eq, b_eq=rhs, bounds=(0, None), method="highs-ds")
    slack = (res.x[len(cols) * k:len(cols) * k + m] - res.x[len(cols) * k + m:]
             if res.status == 0 else np.ones(m))
    dof = model.dof
    worst = np.abs(slack.reshape(-1, dof)).max(axis=1)
    falling = free[worst > 1e-9 * np.abs(rhs).max()]
    return InputError(f"the structure cannot stand under its dead load (no contact forces "
                      f"balance it): {_names(model, falling)} cannot be held (they fall or "
                      "slide under their own weight); check their supports and friction")


def _mechanism(model: Model, contacts: Contacts, force: np.ndarray, relative: np.ndarray,
               velocity: np.ndarray, mu: np.ndarray) -> Mechanism:
    """The joints of the mechanism from the contacts' relative virtual velocities (fastest
    block point at 1 m/s): a point is stationary when |U| <= _STATIONARY, open when U_n
    exceeds it; a joint hinges about its stationary points (2D: one point; 3D: points on a
    line) when its other points open, slides when a point slips (|U_T| > _STATIONARY) on the
    boundary of the dilatancy cone, U_n <= mu |U_T| (+ _STATIONARY), and is open when every
    point opens without that."""
    k, d = contacts.count, model.dim
    tol = _STATIONARY
    cand, ant = contacts.candidate[:k], contacts.antagonist[:k]
    point = contacts.point[:k]
    un = relative[:, 1]
    slip = np.linalg.norm(np.delete(relative, 1, axis=1), axis=1)
    still = np.hypot(un, slip) <= tol
    opens = un > tol
    slides = (slip > tol) & (un <= mu * slip + tol)
    data = {"candidate": cand, "antagonist": ant, "point": point, "frame": contacts.frame[:k],
            "gap": contacts.gap[:k], "force": force}
    pairs, cop, resultant = joint_resultants(data, math.inf)
    joint = joint_index(cand, ant)
    course, left = wall_frame(model)
    size = float(model.body_size[model.body_kind == BodyKind.FREE].min())
    joints = []
    for j, (a, b) in enumerate(pairs):
        rows = np.flatnonzero(joint == j)
        fixed = still[rows]
        hinge, at, line = False, None, None
        if fixed.any() and (opens[rows] | fixed).all() and opens[rows].any():
            ends = _line_of(point[rows[fixed]], 1e-6 * size)
            if ends is not None:
                hinge = True
                at = tuple(map(float, 0.5 * (ends[0] + ends[1])))
                if d == 3:
                    line = tuple(tuple(map(float, e)) for e in ends)
        sliding = bool(slides[rows].any())
        carries = bool(np.isfinite(cop[j, 0]))
        coursed = tuple(course[i] for i in (a, b) if i in course)
        joints.append(Joint(
            bodies=(model.body_name[a], model.body_name[b]),
            hinge=hinge, hinge_point=at, sliding=sliding,
            slip=float(slip[rows].max()) if sliding else 0.0,
            open=bool(opens[rows].all()) and not sliding,
            centre_of_pressure=tuple(map(float, cop[j])),
            force=tuple(map(float, resultant[j])) if carries else (math.nan,) * d,
            courses=coursed or None,
            along=(float((at if hinge else cop[j])[0] - left) if coursed and d == 2
                   else None),
            hinge_line=line))
    speed = np.linalg.norm(velocity[:, :d], axis=1) + np.linalg.norm(
        velocity[:, d:], axis=1) * model.body_radius
    moving = [model.body_name[b] for b in np.flatnonzero(speed > tol)]
    return Mechanism(joints, moving, 0.0)
