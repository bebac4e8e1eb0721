"""The crack pattern of the TU Eindhoven shear wall J4D (p = 0.30 MPa) against the test's:
benchmarks/shear_wall.py with the top beam held horizontal and at its height (DRIVEN) and a
potential crack in the middle of each brick (--split).

Source of the pattern: the walls of Raijmakers & Vermeltfoort (TU Eindhoven, 1992) as
P.B. Lourenco, "Computational strategies for masonry structures", PhD thesis, TU Delft 1996,
ch. 6, and P.B. Lourenco & J.G. Rots, "Multisurface interface model for analysis of masonry
structures", J. Eng. Mech. 123(7) (1997) 660-668, describe them: the pre-compression applied,
then the top pushed sideways with the top beam kept horizontal and its vertical movement
precluded; horizontal tensile (flexural) cracks open early at the bottom and at the top of
the wall, on opposite sides, then a diagonal stepped crack through head and bed joints (and
bricks) runs from one top corner to the opposite bottom corner and the load falls; the
compressed toes crush. (The papers' text could not be read with the tools of the session
that wrote this test, branch crack15; the description is the one its brief gave, from those
papers, BENCHMARKS.md.)

Checked, in measurable terms (b = 0.99 m wide, H = 1.0 m high; pushed towards +x):
- the peak comes after 0.2 mm (the heels begin to crack at 0.3-0.4 mm in these runs), and
  the load falls after it by more than 20 % (measured: 89.3 kN at 0.81 mm, 56.7 kN at
  1.6 mm; 20 %: the smallest fall in BENCHMARKS.md's runs is 32 %): the diagonal crack ends
  the rise.
- at the peak, the ground's bed joint has cracked at the pushed side's heel only (every fully
  cracked point at x < b / 4) and the beam's at the far side only (x > b / 2): the flexural
  cracks, the moment V H / 2 at each end opening that end's joint on its tension side. b / 4
  and b / 2: the heel cracks measured reach 0.17 m and from 0.55 m; a crack along the whole
  joint (sliding, as under a constant vertical load, BENCHMARKS.md) fails both.
- after the peak (1.6 mm), fully cracked joints inside the wall in at least 12 of the 16
  courses (measured 14: the courses next to the toes, where the test's crack ends in crushing,
  may stay uncracked; 12 leaves one more course at each end), both bed-joint points and
  vertical ones (head joints or brick cracks): a stepped crack.
- the least-squares line through the courses' crack centres (median x of a course's cracked
  points) runs from the pushed side's top corner to the far foot: x at the top < b / 3 and at
  the foot > 2 b / 3 (each end within a third of the width of its corner; measured 0.04 and
  0.93 m), at 45 +- 15 deg from the horizontal (measured 48.6): the wall's diagonal is
  atan(H / b) = 45.3 deg; the steepest stair through mortar joints alone,
  atan(course / (unit / 2)) = 29.6 deg, lies outside the band, which is why rigid unsplit
  bricks cannot form this crack (they crack at the heels only, BENCHMARKS.md).

The parameters and their sources (checked for issue 15, branch src15, 2026-11-28): the tables
that hold them, in Lourenco's thesis (ch. 6), Lourenco & Rots (1997), Lourenco, Rots &
Blaauwendraad (Heron 40(4), 1995) and Lourenco's DIANA micro-model guide (TU Delft report
03.21.1.31.35, 1996), could not be read: the stored copies found (scribd, documents.pub) are
served from their first page only, before any table, and Vermeltfoort & Raijmakers' test
reports were not found. So none of these numbers is checked against its source:
- joints (benchmarks/shear_wall.py, p = 0.30 MPa): k_n = 82, k_s = 36 N/mm^3, f_t = 0.25 MPa,
  G_I = 0.018 N/mm, c = 0.35 MPa, tan phi = 0.75, G_II = 0.125 N/mm, as branch shearwall gave
  them for Lourenco's; the one other copy found, a third-party script in a public repository
  (not a publication), lists the same seven as "Lourenco (1994) calibrated values for J4D".
  Lourenco's dilatancy and cap are not modelled.
- bricks: E = 16700 MPa, nu = 0.15, as given (the same script's), rigid here (their
  compliance lumped into the joints).
- brick cracks: f_t = 2.0 MPa, G_I = 0.08 N/mm, as recalled (branch crack15); their shear
  parameters are chosen: c = 2.8 MPa = 1.4 f_t (the joints' own c / f_t), tan phi = 1.0,
  G_II = 0.8 N/mm = 10 G_I. The pattern does not hang on the chosen three (BENCHMARKS.md, same
  run with --brick-shear): with the joints' ratios throughout (tan phi 0.75, G_II = 80 x
  125 / 18 = 556 J/m^2) 88.1 kN at 0.78 mm, 51.5 kN at 1.6 mm, the same heel cracks, cracks
  in 15 of 16 courses, line at 51.5 deg from 0.95 m to 0.15 m; with c = f_t = 2.0 MPa 89.3 kN
  at 0.81 mm, 55.1 kN, 14 courses, 48.6 deg from 0.93 m to 0.04 m: every check below passes
  in both.

Not checked: crushing (no compressive cap in the model) and the peak load (the measured peaks
could not be read here; the held beam's vertical force grows to 3.7 times the pre-compression
by the peak, and without a cap nothing bounds it). The push runs at 0.1 m/s after a 10 ms
press to keep the test short; the benchmark at 0.05 m/s gives the same pattern (peak
88.2 kN at 0.76 mm, crack line at 53 deg from x = 0.90 m at the foot to 0.15 m at the top,
BENCHMARKS.md).
"""

import numpy as np
from shear_wall_model import eindhoven as w

DRIFT, SPEED, PRESS, HOLD = 1.6e-3, 0.1, 0.005, 0.005  # [m], [m/s], [s], [s]


def test_j4d_cracks_at_the_heels_then_along_a_stepped_diagonal():
    u, fx, _, at_peak, _, _, end, _ = w.push(0.30e6, speed=SPEED, drift=DRIFT, press=PRESS,
                                             hold=HOLD, split=True)
    k = int(np.argmax(fx))
    assert u[k] > 0.2e-3
    assert fx[k:].min() < 0.8 * fx[k]
    heels = w.crack_pattern(at_peak)
    assert heels.base.size > 0 and heels.top.size > 0
    assert heels.base.max() < 0.25 * w.WIDTH
    assert heels.top.min() > 0.5 * w.WIDTH
    crack = w.crack_pattern(end)
    assert (~np.isnan(crack.centre)).sum() >= 12
    assert crack.bed > 0 and crack.head + crack.brick > 0
    assert crack.x_top < w.WIDTH / 3.0
    assert crack.x_foot > 2.0 * w.WIDTH / 3.0
    assert abs(crack.angle - 45.0) < 15.0
