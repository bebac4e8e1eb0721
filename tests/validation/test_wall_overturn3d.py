"""A tall slender 3D brick wall overturns out of its plane at the load factor b/h.

Statics of a rigid block of thickness b and height h on a rigid base under its weight m g and
a horizontal load lambda m g normal to its plane (any textbook; e.g. G.W. Housner, Bull.
Seismol. Soc. Am. 53, 1963, for the same block rocking): the moment about the base edge
changes sign at lambda = b/h. A wall of bricks in running bond under a uniform horizontal load
lambda g on every brick reaches that value first at its base joint (a part of height h' above
any bed joint needs b/h' > b/h), and with mu = 0.6 > b/h no joint slides, so the wall
overturns as one block at lambda = b/h.

Model: saxum.structures.wall3d, 12 courses (h = 0.78 m) of 0.25 x 0.12 x 0.065 m bricks
(b = 0.12 m: b/h = 0.1538), 0.5 m long, mu = 0.6, dt = 1e-3 s; the load along y (normal to
the wall). saxum.collapse.critical_value brackets the collapse load factor to 0.5 %; required
(issue 6): within 2 % of b/h. Its mechanism (saxum.mechanism): every brick of the first
course hinges on the ground along the base's far edge (y = b, z = 0), and together these hinge
lines span the wall's length; no joint slides.
"""

import dataclasses

import numpy as np
import pytest

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value
from saxum.structures import wall3d

COURSES, LENGTH, B, BRICK_HEIGHT = 12, 0.5, 0.12, 0.065


def _wall_under(factor):
    model = wall3d(courses=COURSES, length=LENGTH, thickness=B, brick_height=BRICK_HEIGHT,
                   friction=0.6)
    load = (0.0, factor * 9.81, 0.0)
    return sx.Simulation(dataclasses.replace(model, accelerations=(lambda t: load,)), dt=1e-3)


def test_slender_wall_overturns_at_b_over_h():
    ratio = B / (COURSES * BRICK_HEIGHT)
    result = critical_value(_wall_under, 0.8 * ratio, 1.2 * ratio, tolerance=0.005,
                            criterion=CollapseCriterion(duration=1.0))
    assert result.value == pytest.approx(ratio, rel=0.02)
    # it overturns: the top course moves along the load, out of the plane
    trial = result.collapse()
    model, state = trial.simulation.model, trial.state
    top = [b for b, name in enumerate(model.body_name) if name.startswith(f"brick c{COURSES}a")]
    assert (state.body_q[top, 1] - model.body_q0[top, 1]).min() > 0.0
    # the mechanism: one hinge line along the far edge of the base
    mech = trial.mechanism()
    assert mech.hinges and not mech.sliding
    first = sorted(name for name in model.body_name if name.startswith("brick c1a"))
    assert sorted(j.bodies[1] for j in mech.hinges) == first
    assert all(j.bodies[0] == "ground" for j in mech.hinges)
    ends = np.array([end for j in mech.hinges for end in j.hinge_line])
    assert ends[:, 1] == pytest.approx(B, abs=1e-6) and ends[:, 2] == pytest.approx(0, abs=1e-6)
    assert ends[:, 0].min() == pytest.approx(0.0, abs=1e-6)
    assert ends[:, 0].max() == pytest.approx(LENGTH, abs=1e-6)
