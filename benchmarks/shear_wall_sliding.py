"""A clay-brick wall that failed by bed-joint sliding, against its published test: wall
COMP2_5 of Graziotti et al. (2016b), as the EPFL modern masonry walls database quotes it.

Source (secondary; the numbers below are read from it): EPFL-ENAC, modern masonry walls
database, github.com/EPFL-ENAC/eesd-modern-masonry-walls-db,
frontend/public/data/ModernMasonryDatabase_EIA_Database.csv, entries N = 187 (COMP2_4) and 188
(COMP2_5); fields in ModernMasonryDatabase_EIA_Fields.csv. It quotes (primary, not read here)
F. Graziotti, U. Tomassetti, A. Rossi et al., "Shaking table tests on a full-scale clay-brick
masonry house representative of the Groningen building stock and related characterization
tests", Report EUC128/2016U, Eucentre, Pavia, 2016.

Both walls: solid clay bricks (SB-C) 208 x 100 x 50 mm, general-purpose mortar, filled head
joints; 45 courses, H = 2.71 m, L = 2.74 m, t = 0.208 m; f_v0 = 0.15 MPa, mu = 0.55 (the
database's "initial shear strength" and "friction coefficient of masonry"); shear span
H0/H = 0.5 (both ends fixed: the top cannot turn); sigma_0 = 0.30 MPa; 9833 MPa in the
column the database's header calls E_m. Failure modes and peaks (V_max+ / V_max-):
COMP2_5 SL (sliding) 149 / 143.1 kN; COMP2_4 S (shear) 126.1 / 137.1 kN.

Model: rigid bricks in running bond (optionally grouped into larger blocks, `rows` x `units`),
COHESIVE joints with c = f_v0 and tan phi = mu; the bricks' and mortar's compliance lumped into
the joints, 1 / k_n = (row height) / E_m, k_t = k_n / 2.4 (nu = 0.2). The database gives no
tensile bond strength f_t and no fracture energies: they are chosen (defaults f_t = 0.1 MPa,
G_I = 10 J/m^2, G_II = 100 J/m^2) and the run is repeated over them (--sweep). The top beam
is guided (free to move, no rotation) under the constant force sigma_0 L t and pushed sideways
through a frictionless contact at 0.01 m/s, as in benchmarks/shear_wall.py --constant. Gravity
is off: sigma_0 is the database's total axial stress, and the wall's own weight (not given)
would only add to the bottom joint's compression. Forces for the whole wall (t = 0.208 m).

Closed forms it sits between: the residual sliding load mu N = 0.55 x 171.0 kN = 94.0 kN
(N = sigma_0 L t), and the full joint's Mohr-Coulomb strength c L t + mu N = 179.5 kN, which
the end joints of a wall fixed at both ends cannot reach: the moment V H / 2 at each end
opens the joint's heel, and the bond is lost there first.

Run: PYTHONPATH=src python benchmarks/shear_wall_sliding.py [--rows 45 --units 12.5]
[--ft 0.1] [--gi 10] [--gii 100] [--sweep]

Measured (2026-11-28, loaded shared 2-core machine; BENCHMARKS.md has the sweep): brick by
brick (563 blocks, to 4 mm, 588 s) the peak is 138.6 kN at 1.66 mm, then the wall slides on
its top bed joint at mu N = 94.0 kN (SL, as recorded); 9 x 5 blocks, 147.3 kN at 0.77 mm.
"""

import argparse
import math
import time

import numpy as np

import saxum as sx

HEIGHT, LENGTH, THICKNESS, COURSES = 2.71, 2.74, 0.208, 45  # [m], [m], [m], [-]
SIGMA_0, COHESION, MU, E_M = 0.30e6, 0.15e6, 0.55, 9833e6  # [Pa], [Pa], [-], [Pa]
MEASURED = {"COMP2_5": (149.0, 143.1, "SL"), "COMP2_4": (126.1, 137.1, "S")}  # [kN]
N = SIGMA_0 * LENGTH  # [N/m]: the vertical force per metre of depth
SPEED, PRESS, HOLD = 0.01, 0.02, 0.01  # [m/s], [s], [s]


def _rise(t: float) -> float:
    """The vertical force's share at t [s]: a half-cosine rise over PRESS, then 1."""
    return 0.5 * (1.0 - math.cos(math.pi * t / PRESS)) if t < PRESS else 1.0


def build(rows: int = COURSES, units: float = 12.5, f_t: float = 0.1e6, g_i: float = 10.0,
          g_ii: float = 100.0, points: int = 3):
    """(model, beam, pusher): the wall as `rows` courses of `units` blocks in running bond
    (45 x 12.5: the bricks; fewer: each block a group of bricks), a fixed ground, the guided
    top beam under sigma_0 L and its pusher. f_t [Pa], g_i, g_ii [J/m^2]: the joints' chosen
    tensile strength and fracture energies."""
    course, unit = HEIGHT / rows, LENGTH / units
    b = sx.ModelBuilder(gravity=(0.0, 0.0))
    b.add_block([(-0.5, -0.2), (LENGTH + 0.5, -0.2), (LENGTH + 0.5, 0.0), (-0.5, 0.0)],
                kind=sx.BodyKind.FIXED, group="ground")
    whole = int(units)
    for r in range(rows):
        y0, y1 = r * course, (r + 1) * course
        start = 0.0 if r % 2 == 0 else 0.5 * unit
        cuts = [0.0] + [start + k * unit for k in range(1, whole + 1)
                        if start + k * unit < LENGTH - 0.25 * unit] + [LENGTH]
        for x0, x1 in zip(cuts[:-1], cuts[1:], strict=True):
            b.add_block([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], density=1800.0,
                        group="brick")
    beam = b.add_block([(0.0, HEIGHT), (LENGTH, HEIGHT), (LENGTH, HEIGHT + 0.2),
                        (0.0, HEIGHT + 0.2)], density=7850.0, group="beam")
    b.add_force([beam], lambda t: (0.0, -N * _rise(t), 0.0))
    pusher = b.add_block([(-0.1, HEIGHT + 0.02), (0.0, HEIGHT + 0.02), (0.0, HEIGHT + 0.18),
                          (-0.1, HEIGHT + 0.18)], kind=sx.BodyKind.DRIVEN,
                         motion=lambda t: (SPEED if t > PRESS + HOLD else 0.0, 0.0, 0.0),
                         group="pusher")
    k_n = E_M / course  # the wall's vertical stiffness E_m / H, whatever the rows
    joint = sx.ContactLaw(friction=MU, kind=sx.LawKind.COHESIVE, k_n=k_n, k_t=k_n / 2.4,
                          f_t=f_t, cohesion=COHESION, g_i=g_i, g_ii=g_ii, points=points)
    set_laws(b, joint)
    model = b.finalize()
    model.body_inv_mass[beam, 2] = 0.0  # guided: the top cannot turn (H0/H = 0.5)
    return model, beam, pusher


def set_laws(b: sx.ModelBuilder, joint: sx.ContactLaw) -> None:
    """`joint` between bricks, ground and beam (groups "brick", "ground", "beam"); the pusher
    ("pusher") touches the beam without friction, and the beam stays clear of the ground."""
    for a, c in (("brick", "brick"), ("ground", "brick"), ("beam", "brick")):
        b.set_law(a, c, joint)
    for a, c in (("pusher", "beam"), ("pusher", "pusher"), ("beam", "beam"),
                 ("ground", "beam"), ("pusher", "brick"), ("ground", "pusher")):
        b.set_law(a, c, sx.ContactLaw(friction=0.0))


def forces(c: sx.Contacts, beam: int, pusher: int, h: float) -> tuple[float, float]:
    """(H, V) [N/m]: the pusher's horizontal force on the beam and the wall's vertical force
    on it, from the impulses / h."""
    n = c.count
    world = np.einsum("ar,ard->ad", c.impulse[:n], c.frame[:n]) / h
    on_beam = np.where(c.candidate[:n] == beam, 1.0, np.where(c.antagonist[:n] == beam, -1.0,
                                                              0.0))
    pushing = (c.candidate[:n] == pusher) | (c.antagonist[:n] == pusher)
    return float((on_beam * pushing) @ world[:, 0]), float((on_beam * ~pushing) @ world[:, 1])


def push(dt: float = 1e-4, drift: float = 4e-3, **wall):
    """Push the wall to `drift` [m] at the top; returns (top displacements [m], horizontal
    loads [N], vertical loads [N], for the whole wall), the contacts at the end, the model and
    the bed joints' slips (bed_slips) at the peak's step and at the end. `wall`: the
    arguments of build."""
    model, beam, pusher = build(**wall)
    rows = wall.get("rows", COURSES)
    sim = sx.Simulation(model, dt=dt, theta=1.0)
    state = sim.initial_state()
    q0 = state.body_q.copy()
    u, fx, fy = [], [], []
    peak, at_peak = -np.inf, None
    while state.time < PRESS + HOLD + drift / SPEED:
        sim.step(state)
        h_force, v_force = forces(state.contacts, beam, pusher, dt)
        u.append(state.body_q[beam, 0] - q0[beam, 0])
        fx.append(h_force * THICKNESS)
        fy.append(v_force * THICKNESS)
        if fx[-1] > peak:
            peak, at_peak = fx[-1], bed_slips(q0, state.body_q, beam, rows)
    return (np.array(u), np.array(fx), np.array(fy), state.contacts, model, at_peak,
            bed_slips(q0, state.body_q, beam, rows))


def bed_slips(q0: np.ndarray, q: np.ndarray, beam: int, rows: int) -> np.ndarray:
    """(rows + 1,) [m]: the horizontal slip across each bed joint (0: the ground's, rows: the
    beam's), the mean x displacement of the row of blocks above it minus that of the row
    below (the ground's: 0; the beam's own). q0, q: body positions [m, rad] at the start and
    now; the blocks are the bodies between the ground (0) and the beam, as build adds them."""
    course = HEIGHT / rows
    dx = q[:, 0] - q0[:, 0]
    row = np.floor(q0[1:beam, 1] / course).astype(int)
    level = np.bincount(row, weights=dx[1:beam], minlength=rows) / np.bincount(
        row, minlength=rows)
    return np.diff(np.concatenate([[0.0], level, [dx[beam]]]))


def cracked_joints(c: sx.Contacts, model: sx.Model, rows: int) -> dict[str, int]:
    """Counts of fully damaged contact points: in bed joints by row (0: the
    ground joint, rows: the beam's) and in head joints."""
    n = c.count
    broken = c.damage[:n] >= 1.0
    bed = np.abs(c.frame[:n, 1, 1]) > 0.99  # bed joints: normal along y
    level = np.rint(c.point[:n, 1] / (HEIGHT / rows)).astype(int)
    out = {f"bed {k}": int((broken & bed & (level == k)).sum()) for k in range(rows + 1)}
    out["head"] = int((broken & ~bed).sum())
    return {k: v for k, v in out.items() if v}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rows", type=int, default=COURSES)
    parser.add_argument("--units", type=float, default=12.5)
    parser.add_argument("--ft", type=float, default=0.1, help="tensile strength [MPa]")
    parser.add_argument("--gi", type=float, default=10.0, help="G_I [J/m^2]")
    parser.add_argument("--gii", type=float, default=100.0, help="G_II [J/m^2]")
    parser.add_argument("--drift", type=float, default=4e-3, help="[m]")
    parser.add_argument("--points", type=int, default=3, help="contact points per contact")
    parser.add_argument("--sweep", action="store_true",
                        help="repeat over f_t, G_I, G_II (the parameters the source lacks)")
    args = parser.parse_args()
    cases = [(args.ft, args.gi, args.gii)]
    if args.sweep:
        cases = [(0.01, 10.0, 100.0), (0.05, 10.0, 100.0), (0.1, 10.0, 100.0),
                 (0.2, 10.0, 100.0), (0.1, 5.0, 100.0), (0.1, 20.0, 100.0),
                 (0.1, 10.0, 50.0), (0.1, 10.0, 200.0)]
    lt = LENGTH * THICKNESS
    print(f"bounds: mu N = {MU * SIGMA_0 * lt / 1e3:.1f} kN, "
          f"c L t + mu N = {(COHESION + MU * SIGMA_0) * lt / 1e3:.1f} kN; measured "
          + ", ".join(f"{k} {a} / {b} kN ({m})" for k, (a, b, m) in MEASURED.items()))
    for f_t, g_i, g_ii in cases:
        start = time.perf_counter()
        u, fx, fy, contacts, model, _, slips = push(
            drift=args.drift, rows=args.rows, units=args.units, f_t=f_t * 1e6, g_i=g_i,
            g_ii=g_ii, points=args.points)
        k = int(np.argmax(fx))
        print(f"{args.rows} x {args.units} blocks ({model.body_count - 3}), f_t {f_t} MPa, "
              f"G_I {g_i}, G_II {g_ii} J/m^2: peak {fx[k] / 1e3:.1f} kN at "
              f"{u[k] * 1e3:.2f} mm (V {fy[k] / 1e3:.1f} kN), at {u[-1] * 1e3:.2f} mm "
              f"{fx[-1] / 1e3:.1f} kN; cracked at the end "
              f"{cracked_joints(contacts, model, args.rows)}; "
              f"{time.perf_counter() - start:.0f} s")
        top = int(np.argmax(slips))
        print(f"  slip at the end: bed {top} {slips[top] * 1e3:.2f} mm of the top's "
              f"{u[-1] * 1e3:.2f} mm; the others at most "
              f"{np.delete(slips, top).max() * 1e3:.3f} mm")


if __name__ == "__main__":
    main()
