"""A brick wall fixed at both ends, pushed to its peak, against the published test: wall COMP2_5
of Graziotti et al. (2016b), a reduced model of benchmarks/shear_wall_sliding.py.

Source of the measured numbers (secondary: a database that quotes the test report): EPFL-ENAC,
modern masonry walls database, github.com/EPFL-ENAC/eesd-modern-masonry-walls-db,
frontend/public/data/ModernMasonryDatabase_EIA_Database.csv, entries N = 187 (COMP2_4) and 188
(COMP2_5). Primary (not read here): F. Graziotti, U. Tomassetti, A. Rossi et al., "Shaking
table tests on a full-scale clay-brick masonry house representative of the Groningen building
stock and related characterization tests", Report EUC128/2016U, Eucentre, Pavia, 2016.

Two twin walls (45 courses of solid clay bricks, H = 2.71 m, L = 2.74 m, t = 0.208 m,
f_v0 = 0.15 MPa, mu = 0.55, H0/H = 0.5, sigma_0 = 0.30 MPa) reached V_max = 149.0 / 143.1 kN
(COMP2_5, sliding) and 126.1 / 137.1 kN (COMP2_4, shear) in the two directions: the test's own
scatter is 126.1 to 149.0 kN. saxum's rigid-brick model takes c and mu from the source and
chooses what the source lacks (f_t = 0.1 MPa, G_I = 10 J/m^2, G_II = 100 J/m^2, k_n = E_m / h).

Tolerance: the measured range widened by 7 % on each side, the reduced model's margin: its
peak (9 rows of 5 blocks, each a group of 5 x 2.5 bricks: 147.3 kN) stands 6.3 % above that of
the brick-by-brick wall (45 x 12.5 bricks: 138.6 kN), BENCHMARKS.md; the margin is this
reduction's: others stand further off (9 x 2.5 blocks +14.6 %, 15 x 12.5 / 3 +17.7 %). The
parameters the source lacks move the peak further (G_I 5 to 20 J/m^2: -3 % / +3 %; f_t 0.01
to 0.2 MPa: -13 % / +3.5 %, the benchmark's --sweep): the test pins the chosen values. Closed
forms it must respect as well: the peak exceeds the sliding load mu N (the bond carried part
of it) and stays below the whole end joint's Mohr-Coulomb strength c L t + mu N (the end
moment V H / 2 opens the joint's heel before the peak, so that strength is not reached).

The pattern: the database records COMP2_5's failure mode as SL (sliding; its field #30) and
nothing on where it slid; its bilinear idealisation holds its plateau, V_bil+ = 135.2 kN, to
a large drift (delta_u+ = 1.38 %, 37 mm, against COMP2_4's 0.24 %). The peak's model
(9 x 5 blocks) does not slide: it forms a stair-stepped diagonal through bed and head joints
(COMP2_4's S). The reason is the reduction, not the joints: a stair through joints alone
climbs one row per half block, atan(0.301 / 0.274) = 47.7 deg with these blocks, close to the
wall's diagonal atan(H / L) = 44.7 deg, so the diagonal costs joints only; with bricks it
climbs atan(0.0602 / 0.1096) = 28.8 deg and cannot join the corners without breaking bricks,
which rigid bricks cannot do, so the brick-by-brick wall slides on an end bed joint. The
pattern test therefore groups the bricks as 5 courses x 5 bricks per block (9 rows of 2.5
blocks of 1.096 x 0.301 m): the bricks' aspect ratio, hence their stair angle, with 11 points
per contact, the bricks' point spacing (0.11 m: 3 points per 0.219 m brick), both fixed from
the geometry before the run. It slides on the beam's bed joint as the brick-by-brick wall does
(BENCHMARKS.md). Its peak, 158.8 kN at 0.39 mm, stands 14.6 % above the brick-by-brick wall's
and 6.6 % above the test's largest: the peak depends on the reduction (15 rows of 12.5 / 3
blocks: 163.1 kN, sliding on the ground's joint), so here it is held to the closed forms only.
"""

import numpy as np
from shear_wall_model import wall

MEASURED_LOW, MEASURED_HIGH = 126.1e3, 149.0e3  # [N]: COMP2_4's V_max+, COMP2_5's V_max+
MARGIN = 0.07  # the reduced model's margin (module doc)


def test_comp2_5_peak_within_the_tests_scatter():
    u, fx, fy, _, _, _, _ = wall.push(drift=1.5e-3, rows=9, units=5.0, f_t=0.1e6, g_i=10.0,
                                      g_ii=100.0)
    k = int(np.argmax(fx))
    peak = fx[k]
    # the wall's peak, not the spike as the pusher starts (BENCHMARKS.md): it came at 0.77 mm
    assert u[k] > 0.2e-3
    lt = wall.LENGTH * wall.THICKNESS  # [m^2]
    n = wall.SIGMA_0 * lt  # [N]
    # the beam carries sigma_0 L t at the peak (guided beam, constant vertical force)
    assert abs(fy[k] / n - 1.0) < 0.01
    # the peak is passed within the run: the load has fallen after it
    assert fx[-1] < 0.95 * peak
    assert wall.MU * n < peak < (wall.COHESION + wall.MU * wall.SIGMA_0) * lt
    assert (1.0 - MARGIN) * MEASURED_LOW <= peak <= (1.0 + MARGIN) * MEASURED_HIGH


def test_comp2_5_slides_on_an_end_bed_joint():
    u, fx, _, _, _, at_peak, end = wall.push(drift=2e-3, rows=9, units=2.5, points=11,
                                             f_t=0.1e6, g_i=10.0, g_ii=100.0)
    k = int(np.argmax(fx))
    assert u[k] > 0.2e-3  # the wall's peak, not the push's start-up spike (measured 0.39 mm)
    lt = wall.LENGTH * wall.THICKNESS  # [m^2]
    n = wall.SIGMA_0 * lt  # [N]
    assert wall.MU * n < fx[k] < (wall.COHESION + wall.MU * wall.SIGMA_0) * lt
    # after the peak the top's displacement goes into one bed joint's slip: measured 105 %
    # of it (the rest of the wall springs back as the load falls to mu N); the others move
    # by less than 5 % of it (measured 2.4 %: elastic shear, no slip), so the wall above the
    # joint moves as one body: sliding, SL
    slip, top = end - at_peak, u[-1] - u[k]
    j = int(np.argmax(slip))
    assert slip[j] > 0.9 * top
    assert np.abs(np.delete(slip, j)).max() < 0.05 * top
    # an end joint (0: the ground's, 9: the beam's; measured 9): the end moments V H / 2
    # open the end joints' heels first (a closed form of the guided wall, not the test's
    # record: the database does not say where COMP2_5 slid)
    assert j in (0, 9)
    # then it slides at Coulomb's mu N: its points are fully cracked Coulomb contacts whose
    # normal forces sum to N (measured within 0.2 % over the last 0.3 mm; 1 %: the residual
    # tolerance of test_shear_wall_bounds.py, the joints' damped vibration)
    assert np.all(np.abs(fx[u > u[-1] - 0.3e-3] / (wall.MU * n) - 1.0) < 0.01)
