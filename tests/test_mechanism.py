"""Joint resultants and the thrust line, on hand-made contacts with known answers."""

import numpy as np
import pytest

from saxum.mechanism import joint_resultants, thrust_line


def _contacts(pairs, points, rn, rt=None, gap=None):
    k = len(pairs)
    up = np.tile(np.array([[1.0, 0.0], [0.0, 1.0]]), (k, 1, 1))  # t = x, n = y
    rt = np.zeros(k) if rt is None else np.asarray(rt, float)
    return {"candidate": np.array([p[0] for p in pairs]),
            "antagonist": np.array([p[1] for p in pairs]),
            "point": np.asarray(points, float), "frame": up,
            "gap": np.zeros(k) if gap is None else np.asarray(gap, float),
            "force": np.column_stack((rt, np.asarray(rn, float)))}


def test_centre_of_pressure_and_resultant():
    c = _contacts([(2, 1), (1, 2), (3, 1)], [(0.0, 0.0), (1.0, 0.0), (5.0, 1.0)],
                  rn=[1.0, 3.0, 2.0], rt=[0.5, -0.1, 0.0])
    pairs, cop, resultant = joint_resultants(c, gap_tolerance=1e-6)
    assert pairs.tolist() == [[1, 2], [1, 3]]
    assert cop[0] == pytest.approx([0.75, 0.0])  # (1 * 0 + 3 * 1) / 4
    assert resultant[0] == pytest.approx([0.4, 4.0])
    assert cop[1] == pytest.approx([5.0, 1.0]) and resultant[1] == pytest.approx([0.0, 2.0])


def test_open_points_carry_nothing_and_unloaded_joints_have_no_centre():
    c = _contacts([(1, 2), (1, 2), (3, 4)], [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0)],
                  rn=[1.0, 3.0, 0.0], gap=[0.0, 1e-3, 0.0])
    _, cop, _ = joint_resultants(c, gap_tolerance=1e-6)
    assert cop[0] == pytest.approx([0.0, 0.0])
    assert np.isnan(cop[1]).all()


def test_thrust_line_is_ordered_about_the_centre():
    # springings a hair below the centre's level must still be the ends of the line
    angles = np.radians([180.0 + 1e-9, 30.0, 90.0, -1e-9])
    pts = np.column_stack((np.cos(angles), np.sin(angles)))
    c = _contacts([(1, 2), (2, 3), (3, 4), (4, 5)], pts, rn=[1.0, 1.0, 1.0, 1.0])
    line = thrust_line(c, 1e-6, centre=(0.0, 0.0))
    assert line == pytest.approx(pts[[0, 2, 1, 3]])
