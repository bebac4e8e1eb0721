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
the brick-by-brick wall (45 x 12.5 bricks: 138.6 kN), BENCHMARKS.md. The parameters the source
lacks move the peak further (G_I 5 to 20 J/m^2: -3 % / +3 %; f_t 0.01 to 0.2 MPa: -13 % /
+3.5 %, the benchmark's --sweep): the test pins the chosen values. Closed
forms it must respect as well: the peak exceeds the sliding load mu N (the bond carried part
of it) and stays below the whole end joint's Mohr-Coulomb strength c L t + mu N (the end
moment V H / 2 opens the joint's heel before the peak, so that strength is not reached).
The crack pattern is not checked: this reduced model forms COMP2_4's stair-stepped diagonal,
not COMP2_5's sliding on the top bed joint, which the brick-by-brick wall (588 s) shows
(BENCHMARKS.md, "Masonry shear walls").
"""

import numpy as np
from shear_wall_model import wall

MEASURED_LOW, MEASURED_HIGH = 126.1e3, 149.0e3  # [N]: COMP2_4's V_max+, COMP2_5's V_max+
MARGIN = 0.07  # the reduced model's margin (module doc)


def test_comp2_5_peak_within_the_tests_scatter():
    u, fx, fy, _, _ = wall.push(drift=1.5e-3, rows=9, units=5.0, f_t=0.1e6, g_i=10.0,
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
