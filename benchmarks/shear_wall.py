"""A masonry shear wall pushed at its top: the TU Eindhoven walls of Vermeltfoort and
Raijmakers as micro-modelled by Lourenco, with rigid bricks and COHESIVE joints.

Wall (P.B. Lourenco, "Computational strategies for masonry structures", PhD thesis, TU Delft
1996, ch. 6, and P.B. Lourenco & J.G. Rots, J. Eng. Mech. 123 (1997) 660-668): 990 mm wide,
1000 mm high, 100 mm thick, bricks 210 x 52 x 100 mm, 10 mm mortar joints, 18 courses of
which the bottom and top ones are clamped in steel beams (here: a fixed ground and a
DRIVEN top beam; 16 free courses, 4.5 bricks each, running bond). A vertical pre-compression
p is applied by the top beam, which is then pushed horizontally, kept horizontal and with no
vertical movement (displacement control). 2D, per metre of depth; forces are reported for
the 100 mm thick wall [kN].

Joints (Lourenco's interface for the walls with p = 0.30 MPa, as we have them, not checked
against the thesis or the paper, which could not be read: tests/validation/
test_shear_wall_cracks.py lists each number's basis): k_n = 82
N/mm^3, k_s = 36 N/mm^3, f_t = 0.25 MPa, G_I = 0.018 N/mm, c = 0.35 MPa, tan phi = 0.75,
G_II = 0.125 N/mm. Lourenco's bricks are elastic (E = 16700 MPa, nu = 0.15); rigid bricks
with the unit's compliance lumped into the joints is the usual DEM simplification:
1 / k = 1 / k_n + l / E (l the brick's height for bed joints, its length for head joints),
1 / k_t = 1 / k_s + l / G. Not modelled: dilatancy, which Lourenco's model has; the
compressive cap (crushing of the toes) only with --cap (below).

Compression cap (--cap, branch cap15): the mortar joints (bed and head, not the brick cracks)
crush under saxum.laws' cap, sigma^2 + C_ss tau^2 <= sigma_c(w)^2 with exponential
softening sigma_c = f_c exp(-f_c w / G_fc), with the values we recall for Lourenco's J4D
interface, f_c = 10.5 MPa, G_fc = 5 N/mm, C_ss = 9.0 (recalled, not read from the papers
here), or --f-c, --c-ss. Lourenco's cap also hardens from f_c / 3 to f_c first: so does
this one with --kappa-p (branch cap15h; the plastic closure at the peak [mm]; 0.09 mm is the
value we recall for J4D, not read from the papers either), else it is elastic up to the cap.

Potential brick cracks (--split; Lourenco's model has one vertical interface in the middle
of each brick): each brick is two rigid halves joined by a COHESIVE interface with the
brick's strength, f_t = 2.0 MPa and G_I = 0.08 N/mm (Lourenco & Rots 1997's values for
the bricks, as recalled, not checked against the paper, which could not be read) and, chosen
(no source read), c = 2.8 MPa (1.4 f_t, the joints' c / f_t), tan phi = 1.0, G_II = 0.8 N/mm
(10 G_I; --brick-shear C TAN_PHI G_II changes the three), a dummy stiffness 1e6 N/mm^3 in
series with half the brick's length; the head joints then carry the other half.

Run: PYTHONPATH=src python benchmarks/shear_wall.py [--precompression 0.30] [--split]
[--cap [--f-c 10.5] [--c-ss 9] [--kappa-p 0.09]] [--constant] [--speed 0.01]
[--press 0.05 --hold 0.05] [--figure PNG] [--figure-end PNG] [--brick-shear 2.8 1.0 800]
Prints the peak horizontal load and where it occurred, the cracked (and crushed) joints at
the peak and at the end (crack_pattern: the ground's and the beam's joints, and the line
through the courses' crack centres inside), the run's wall time and the load-displacement
curve.

Measured (2026-11-28, p = 0.30 MPa, dt = 1e-4 s, theta = 1, 0.01 m/s, loaded 2-core
machine, 189 s): the pre-compression is 29.7 kN as it should be; the horizontal load is
36 kN at 0.3 mm, 75 kN at 1 mm and still rising at 3 mm (143 kN), with the vertical reaction
rising with it (185 kN at 3 mm): with the beam held at its height, the wall's diagonal
strut lifts it, and without the compressive cap nothing limits that confined strength; the
whole bricks crack at the heels only. With --split (branch crack15, 0.1 m/s after a 10 ms
press, to 1.6 mm): 89.3 kN at 0.81 mm (vertical force 109.5 kN), then a stepped diagonal
crack through bed joints, head joints and bricks from the top of the pushed side to the
far foot and the load falls to 56.7 kN: the tests' pattern (tests/validation/
test_shear_wall_cracks.py; whole rigid bricks cannot form it: the steepest stair through
the joints alone rises at 29.6 deg, the wall's diagonal at 45.3 deg). With --constant (the
beam guided without rotation under a constant vertical load, pushed by a block): 36 kN at
0.3 mm, a plateau of 30-33 kN, a spike of 34.5 kN at 1.35 mm as the bed joints under the
beam and on the ground slide, then 22.8 kN = tan phi x the vertical load (144 s); the
diagonal does not form, with --split neither (the wall slides on those joints). The measured
peak loads are still to be checked in the thesis (we could not read them: branch
shearwall's report). With --cap (f_c 10.5 MPa, C_ss 9): 82.1 kN at 0.84 mm; the normal
cap alone (--c-ss 0) leaves the peak at 89.3 kN (f_c = 3.5 MPa: 78.0 kN); the ellipse at
Lourenco's initial yield f_c / 3 (--f-c 3.5) gives 42.4 kN at 0.47 mm. The ~50 kN the test
is reported to have reached lies between. With the cap hardening from f_c / 3 to f_c at
kappa_p = 0.09 mm (--cap --kappa-p 0.09, branch cap15h) the peak is 88.1 kN at 1.04 mm
(C_ss 9; 89.8 kN with --c-ss 0): the hardening does not close the gap; BENCHMARKS.md has
the tables.

What saxum can claim here, without the measured peaks, is the joints' Mohr-Coulomb bound: every
bed joint spans the wall's width b, so H <= c b t + tan phi V (56.9 kN at p = 0.30 MPa:
0.35 MPa x 990 mm x 100 mm + 0.75 x 29.7 kN), and once a bed joint has broken the wall slides
at tan phi V. tests/validation/test_shear_wall_bounds.py checks both on a small wall under
the --constant boundary conditions (gravity off, so that V is the same on every joint).
"""

import argparse
import math
import time
from typing import NamedTuple

import numpy as np

import saxum as sx
from saxum.laws import NO_CONTACT, LawKind

THICKNESS = 0.1  # [m]: the wall's depth, to turn N/m into N
WIDTH, HEIGHT, COURSES = 0.99, 1.0, 16  # [m], [m], free courses
UNIT = WIDTH / 4.5  # [m]: brick length plus a head joint
COURSE = HEIGHT / COURSES  # [m]: brick height plus a bed joint
BRICK_L, BRICK_H = 0.21, 0.052  # [m]
E_BRICK, NU_BRICK = 16.7e9, 0.15  # [Pa], [-]
K_N, K_S = 82e9, 36e9  # [Pa/m]
F_T, G_I, COHESION, TAN_PHI, G_II = 0.25e6, 18.0, 0.35e6, 0.75, 125.0  # [Pa], [J/m^2], ...
DENSITY = 1800.0  # [kg/m^3]
F_T_BRICK, G_I_BRICK, K_BRICK = 2.0e6, 80.0, 1.0e15  # [Pa], [J/m^2], [Pa/m]
JOINT_SHARE = 5e-3  # [m]: the shortest joint's points stand for 10 mm or more
C_BRICK, TAN_PHI_BRICK, G_II_BRICK = 2.8e6, 1.0, 800.0  # [Pa], [-], [J/m^2]
F_C, G_FC, C_SS = 10.5e6, 5000.0, 9.0  # [Pa], [J/m^2], [-]: the joints' cap (--cap; doc)


def lumped(k_joint: float, length: float, modulus: float) -> float:
    """Joint stiffness [Pa/m] with a unit's compliance length / modulus in series."""
    return 1.0 / (1.0 / k_joint + length / modulus)


def joint_law(length: float, cap: tuple[float, float, float] = (0.0, 0.0, 0.0)
              ) -> sx.ContactLaw:
    """The cohesive law of a joint across a brick dimension `length` [m]; cap = (f_c [Pa],
    C_ss [-], kappa_p [m]), f_c > 0: with a compression cap of strength f_c, G_FC and C_ss,
    hardening from f_c / 3 to f_c at the plastic closure kappa_p if kappa_p > 0."""
    g = E_BRICK / (2.0 * (1.0 + NU_BRICK))
    return sx.ContactLaw(friction=TAN_PHI, kind=LawKind.COHESIVE,
                         k_n=lumped(K_N, length, E_BRICK), k_t=lumped(K_S, length, g),
                         f_t=F_T, cohesion=COHESION, g_i=G_I, g_ii=G_II, points=3,
                         f_c=cap[0], g_fc=G_FC if cap[0] > 0.0 else 0.0, c_ss=cap[1],
                         kappa_p=cap[2])


def brick_law(shear: tuple[float, float, float] = (C_BRICK, TAN_PHI_BRICK, G_II_BRICK)
              ) -> sx.ContactLaw:
    """The potential crack in the middle of a brick (Lourenco's micro-model): the brick's
    strength F_T_BRICK, G_I_BRICK, half its length's compliance on each side; shear: its
    cohesion [Pa], friction [-] and G_II [J/m^2] (module doc: chosen, not sourced)."""
    g = E_BRICK / (2.0 * (1.0 + NU_BRICK))
    cohesion, friction, g_ii = shear
    return sx.ContactLaw(friction=friction, kind=LawKind.COHESIVE,
                         k_n=lumped(K_BRICK, 0.5 * BRICK_L, E_BRICK),
                         k_t=lumped(K_BRICK, 0.5 * BRICK_L, g), f_t=F_T_BRICK,
                         cohesion=cohesion, g_i=G_I_BRICK, g_ii=g_ii, points=3)


def smooth(t: float, t0: float, t1: float) -> float:
    """Rate of a smooth (half-cosine) rise from 0 to 1 over [t0, t1] [1/s]."""
    if t <= t0 or t >= t1:
        return 0.0
    return 0.5 * math.pi / (t1 - t0) * math.sin(math.pi * (t - t0) / (t1 - t0))


def build(precompression: float, press: float, hold: float, speed: float,
          constant: bool = False, split: bool = False,
          brick_shear: tuple[float, float, float] = (C_BRICK, TAN_PHI_BRICK, G_II_BRICK),
          cap: tuple[float, float, float] = (0.0, 0.0, 0.0)):
    """(model, beam index, index of what pushes the beam or -1): the wall, the ground and the top
    beam. The beam is DRIVEN: it lowers by the bed joints' closure under `precompression`
    [Pa] over `press` [s], holds for `hold` [s], then moves sideways at `speed` [m/s]; or,
    `constant`, FREE with its rotation held (a guided beam: its inverse rotational inertia
    set to 0) under the force precompression x width, rising over `press`, and pushed
    sideways by a DRIVEN block at its left end (a frictionless contact). brick_shear: the
    brick cracks' (split) cohesion [Pa], friction [-], G_II [J/m^2]. cap: the mortar
    joints' (f_c [Pa], C_ss [-], kappa_p [m]) (joint_law)."""
    b = sx.ModelBuilder()
    b.add_block([(-0.5, -0.2), (WIDTH + 0.5, -0.2), (WIDTH + 0.5, 0.0), (-0.5, 0.0)],
                kind=sx.BodyKind.FIXED, group="ground", name="ground")
    courses = []
    for c in range(COURSES):
        y0, y1 = c * COURSE, (c + 1) * COURSE
        odd = c % 2 == 0  # course 1 at the bottom
        cuts = ([k * UNIT for k in range(5)] + [WIDTH] if odd
                else [0.0] + [0.5 * UNIT + k * UNIT for k in range(5)])
        parity = "odd" if odd else "even"
        if split:
            # each brick's middle, a potential crack (Lourenco's model): the halves alternate
            # over four groups so that half-against-half (brick) and brick-against-brick
            # (head joint) pairs get their own laws
            pieces = []
            for x0, x1 in zip(cuts[:-1], cuts[1:], strict=True):
                pieces += [(x0, 0.5 * (x0 + x1)), (0.5 * (x0 + x1), x1)] if x1 - x0 > 0.75 * UNIT \
                    else [(x0, x1)]
            # a half brick at a course's end: its one face is a head joint (phase 1 or 3)
            phase = 0 if cuts[1] - cuts[0] > 0.75 * UNIT else 1
            groups = [f"{parity}{(phase + k) % 4}" for k in range(len(pieces))]
        else:
            pieces = list(zip(cuts[:-1], cuts[1:], strict=True))
            groups = [parity] * len(pieces)
        for k, ((x0, x1), g) in enumerate(zip(pieces, groups, strict=True)):
            b.add_block([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], density=DENSITY,
                        group=g, name=f"brick c{c + 1}p{k + 1}")
        courses.append(sorted(set(groups)))
    # the bed joints in series close by their stress / k each: 15 between courses, ground
    # and beam, each under p and the weight of the courses above it
    bed = joint_law(BRICK_H, cap)
    weight = DENSITY * 9.81 * COURSE  # [Pa] per course
    closure = sum(precompression + weight * (COURSES - j) for j in range(COURSES + 1)) / bed.k_n

    def motion(t: float) -> tuple[float, float, float]:
        vx = speed if t > press + hold else 0.0
        return vx, -closure * smooth(t, 0.0, press), 0.0

    top = [(0.0, HEIGHT), (WIDTH, HEIGHT), (WIDTH, HEIGHT + 0.1), (0.0, HEIGHT + 0.1)]
    if constant:
        beam = b.add_block(top, density=7850.0, group="beam", name="top beam")
        b.add_force([beam], lambda t: (0.0, -precompression * WIDTH * min(
            1.0, 0.5 * (1.0 - math.cos(math.pi * min(t, press) / press))), 0.0))
        pusher = b.add_block([(-0.1, HEIGHT + 0.01), (0.0, HEIGHT + 0.01), (0.0, HEIGHT + 0.09),
                              (-0.1, HEIGHT + 0.09)], kind=sx.BodyKind.DRIVEN,
                             motion=lambda t: (speed if t > press + hold else 0.0, 0.0, 0.0),
                             group="pusher", name="pusher")
        for g in ("beam", "pusher"):
            b.set_law(g, g, sx.ContactLaw(friction=0.0))
        b.set_law("pusher", "beam", sx.ContactLaw(friction=0.0))
        for g in ["ground"] + courses[0] + courses[1]:
            b.set_law("pusher", g, sx.ContactLaw(friction=0.0))
    else:
        beam = b.add_block(top, kind=sx.BodyKind.DRIVEN, motion=motion, group="beam",
                           name="top beam")
        pusher = -1
    odd, even = courses[0], courses[1]
    for a, c in ([(o, e) for o in odd for e in even] + [("ground", g) for g in odd + even]
                 + [("beam", g) for g in odd + even]):
        b.set_law(a, c, bed)
    if split:
        head, brick = joint_law(0.5 * BRICK_L, cap), brick_law(brick_shear)
        for parity in ("odd", "even"):
            for i in range(4):
                for j in range(i, 4):
                    law = {1: brick if i % 2 == 0 else head, 3: head}.get(j - i, NO_CONTACT)
                    b.set_law(f"{parity}{i}", f"{parity}{j}", law)
    else:
        head = joint_law(BRICK_L, cap)
        b.set_law("odd", "odd", head)
        b.set_law("even", "even", head)
    b.set_law("ground", "beam", sx.ContactLaw(friction=TAN_PHI))
    model = b.finalize()
    if constant:
        model.body_inv_mass[beam, 2] = 0.0
    return model, beam, pusher


def beam_force(c: sx.Contacts, beam: int, h: float, pusher: int) -> np.ndarray:
    """The force of the wall on the beam [N/m], world axes: the impulses / h of the beam's
    contacts but that with the pusher."""
    n = c.count
    world = np.einsum("ar,ard->ad", c.impulse[:n], c.frame[:n]) / h
    other = (c.candidate[:n] != pusher) & (c.antagonist[:n] != pusher)
    sign = np.where(c.candidate[:n] == beam, 1.0,
                    np.where(c.antagonist[:n] == beam, -1.0, 0.0)) * other
    return sign @ world


def draw(model: sx.Model, q: np.ndarray, contacts: sx.Contacts, path: str, title: str) -> None:
    """The blocks at q [m, rad] and the joints' contact points coloured by damage, the fully
    cracked ones drawn as red strokes along the joint over the length they stand for, into
    `path`."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.collections import LineCollection

    fig, ax = plt.subplots(figsize=(5.5, 6))
    for k in range(model.body_count):
        c, s = math.cos(q[k, 2]), math.sin(q[k, 2])
        local = model.vertex_local[model.body_vertex_start[k]:model.body_vertex_start[k + 1]]
        world = local @ np.array([[c, s], [-s, c]]) + q[k, :2]
        ax.fill(world[:, 0], world[:, 1], facecolor="#e8d9c0", edgecolor="#8a7550", lw=0.5)
    n = contacts.count
    joint = contacts.area[:n] > JOINT_SHARE  # not a corner touching a corner
    damage = contacts.damage[:n]
    dots = ax.scatter(contacts.point[:n][joint, 0], contacts.point[:n][joint, 1],
                      c=damage[joint], cmap="inferno_r", vmin=0.0, vmax=1.0, s=5, zorder=3)
    cracked = joint & (damage >= 1.0)
    half = 0.5 * contacts.area[:n][cracked, None] * contacts.frame[:n][cracked, 0]
    centre = contacts.point[:n][cracked]
    ax.add_collection(LineCollection(np.stack([centre - half, centre + half], axis=1),
                                     colors="red", linewidths=2.0, zorder=4))
    fig.colorbar(dots, ax=ax, label="damage d (red: cracked, d = 1)", shrink=0.7)
    ax.set_xlim(-0.15, WIDTH + 0.1)
    ax.set_ylim(-0.1, HEIGHT + 0.15)
    ax.set_aspect("equal")
    ax.set_title(title, fontsize=9)
    fig.savefig(path, dpi=120, bbox_inches="tight")


def push(precompression: float, *, dt: float = 1e-4, speed: float = 0.01, drift: float = 3e-3,
         press: float = 0.05, hold: float = 0.05, constant: bool = False, split: bool = False,
         brick_shear: tuple[float, float, float] = (C_BRICK, TAN_PHI_BRICK, G_II_BRICK),
         cap: tuple[float, float, float] = (0.0, 0.0, 0.0)):
    """Run the test; returns (top displacements [m], horizontal loads [N] on the 100 mm wall,
    vertical loads [N], the contacts and positions at the peak's step, the model, the contacts
    and positions at the end). brick_shear, cap: as build's."""
    model, beam, pusher = build(precompression, press, hold, speed, constant, split,
                                brick_shear, cap)
    sim = sx.Simulation(model, dt=dt, theta=1.0)
    state = sim.initial_state()
    x0 = state.body_q[beam, 0]
    u, fx, fy = [], [], []
    peak, at_peak, q_peak = -np.inf, None, None
    end = press + hold + drift / speed
    while state.time < end:
        sim.step(state)
        f = beam_force(state.contacts, beam, dt, pusher) * THICKNESS
        u.append(state.body_q[beam, 0] - x0)
        fx.append(-f[0])
        fy.append(f[1])
        if -f[0] > peak:
            peak, at_peak, q_peak = -f[0], state.contacts.copy(), state.body_q.copy()
    return (np.array(u), np.array(fx), np.array(fy), at_peak, q_peak, model, state.contacts,
            state.body_q)


class CrackPattern(NamedTuple):
    """The fully cracked joint points (damage 1) of a pushed wall. base, top: x [m] of those
    in the ground's and the beam's bed joints; centre: per course (bottom first), the median x
    [m] of those inside the wall (bed joints above the course's bottom, vertical joints and
    brick cracks in it), NaN where none; angle [deg] and x at the wall's foot and top [m] of
    the least-squares line x = a + b y through the centres; bed, head, brick: counts inside
    the wall."""

    base: np.ndarray
    top: np.ndarray
    centre: np.ndarray
    angle: float
    x_foot: float
    x_top: float
    bed: int
    head: int
    brick: int


def crack_pattern(c: sx.Contacts) -> CrackPattern:
    """The cracked points of `c`. Points that stand for less than JOINT_SHARE of a joint are
    left out: corners touching corners where a brick crack meets a head joint, whose length
    is the blocks' overlap (at most their slip, a fraction of a millimetre before the wall
    fails), not a joint."""
    n = c.count
    x, y = c.point[:n, 0], c.point[:n, 1]
    cracked = (c.damage[:n] >= 1.0) & (c.area[:n] > JOINT_SHARE)
    bed = np.abs(c.frame[:n, 1, 1]) > 0.99  # frame (t, n): n along y
    level = np.rint(y / COURSE).astype(int)  # a bed joint's: 0 the ground's
    course = np.where(bed, level, np.floor(y / COURSE).astype(int))
    base = cracked & bed & (level == 0)
    top = cracked & bed & (level == COURSES)
    inner = cracked & ~base & ~top
    centre = np.array([np.median(x[inner & (course == k)]) if (inner & (course == k)).any()
                       else np.nan for k in range(COURSES)])
    y_mid = (np.arange(COURSES) + 0.5) * COURSE
    known = ~np.isnan(centre)
    b, a = np.polyfit(y_mid[known], centre[known], 1) if known.sum() > 1 else (np.nan, np.nan)
    # head joints at multiples of UNIT in courses 1, 3, ... (index even), shifted by UNIT / 2
    # in the others; brick cracks half-way between
    shift = np.where(course % 2 == 0, 0.0, 0.5 * UNIT)
    off = np.abs((x - shift) / UNIT - np.rint((x - shift) / UNIT))
    vertical = inner & ~bed
    return CrackPattern(x[base], x[top], centre, float(np.degrees(np.arctan2(1.0, -b))),
                        float(a), float(a + b * HEIGHT), int((inner & bed).sum()),
                        int((vertical & (off < 0.25)).sum()), int((vertical & (off >= 0.25)).sum()))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--precompression", type=float, default=0.30, help="p [MPa]")
    parser.add_argument("--dt", type=float, default=1e-4)
    parser.add_argument("--speed", type=float, default=0.01, help="[m/s]")
    parser.add_argument("--drift", type=float, default=3e-3, help="[m]")
    parser.add_argument("--press", type=float, default=0.05,
                        help="[s]: the pre-compression's rise")
    parser.add_argument("--hold", type=float, default=0.05, help="[s]: held before the push")
    parser.add_argument("--figure", default=None, help="PNG of the damage at the peak")
    parser.add_argument("--figure-end", default=None, help="PNG of the damage at the end")
    parser.add_argument("--constant", action="store_true",
                        help="hold the vertical load (a guided beam pushed by a block)")
    parser.add_argument("--split", action="store_true",
                        help="a potential crack in the middle of each brick (Lourenco's model)")
    parser.add_argument("--brick-shear", type=float, nargs=3, metavar=("C", "TAN_PHI", "G_II"),
                        default=(C_BRICK / 1e6, TAN_PHI_BRICK, G_II_BRICK),
                        help="the brick cracks' cohesion [MPa], friction, G_II [J/m^2]")
    parser.add_argument("--cap", action="store_true",
                        help="the mortar joints crush (compression cap f_c, G_fc)")
    parser.add_argument("--f-c", type=float, default=F_C / 1e6,
                        help="the cap's f_c [MPa] (with --cap)")
    parser.add_argument("--c-ss", type=float, default=C_SS,
                        help="the cap's C_ss [-] (with --cap)")
    parser.add_argument("--kappa-p", type=float, default=0.0,
                        help="the plastic closure [mm] at which the cap, hardening from f_c / 3,"
                             " reaches f_c (with --cap; 0: no hardening; Lourenco's: 0.09)")
    args = parser.parse_args()
    start = time.perf_counter()
    u, fx, fy, contacts, q, model, end, q_end = push(
        args.precompression * 1e6, dt=args.dt, speed=args.speed, drift=args.drift,
        press=args.press, hold=args.hold, constant=args.constant, split=args.split,
        brick_shear=(args.brick_shear[0] * 1e6, args.brick_shear[1], args.brick_shear[2]),
        cap=(args.f_c * 1e6, args.c_ss, args.kappa_p * 1e-3) if args.cap else (0.0, 0.0, 0.0))
    wall_time = time.perf_counter() - start
    k = int(np.argmax(fx))
    n = contacts.count
    print(f"p = {args.precompression} MPa: vertical load {fy[k] / 1e3:.1f} kN at the peak "
          f"(p b t = {args.precompression * WIDTH * THICKNESS * 1e3:.1f} kN)")
    print(f"peak horizontal load {fx[k] / 1e3:.1f} kN at u = {u[k] * 1e3:.2f} mm; "
          f"at the end ({u[-1] * 1e3:.2f} mm) {fx[-1] / 1e3:.1f} kN")
    joint = contacts.area[:n] > JOINT_SHARE
    print(f"joint points at the peak: {int(joint.sum())}, damaged "
          f"{int((joint & (contacts.damage[:n] > 0)).sum())}, cracked "
          f"{int((joint & (contacts.damage[:n] >= 1)).sum())}, crushed "
          f"{int((joint & (contacts.crush[:n] > 0)).sum())}; wall time {wall_time:.0f} s")
    for when, c in (("at the peak", contacts), ("at the end", end)):
        p = crack_pattern(c)
        print(f"cracks {when}: ground joint x {np.round(np.sort(p.base), 2)} m, beam's joint x "
              f"{np.round(np.sort(p.top), 2)} m; inside: {p.bed} bed, {p.head} head, {p.brick} "
              f"brick points, in {int((~np.isnan(p.centre)).sum())} of {COURSES} courses, "
              f"their centres' line at {p.angle:.1f} deg from x = {p.x_foot:.2f} m (foot) to "
              f"{p.x_top:.2f} m (top)")
    if args.figure:
        draw(model, q, contacts, args.figure,
             f"p = {args.precompression} MPa, peak {fx[k] / 1e3:.1f} kN at "
             f"{u[k] * 1e3:.2f} mm: damage at the peak")
    if args.figure_end:
        draw(model, q_end, end, args.figure_end,
             f"p = {args.precompression} MPa, peak {fx[k] / 1e3:.1f} kN at {u[k] * 1e3:.2f} mm; "
             f"damage at {u[-1] * 1e3:.2f} mm ({fx[-1] / 1e3:.1f} kN)")
    for i in range(0, len(u), max(1, len(u) // 40)):
        print(f"  u = {u[i] * 1e3:6.3f} mm  H = {fx[i] / 1e3:7.2f} kN  V = {fy[i] / 1e3:7.2f} kN")


if __name__ == "__main__":
    main()
