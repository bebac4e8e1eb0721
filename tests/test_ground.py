"""Ground motion: readers (PEER .AT2, CSV), pulses, baseline correction, bad files."""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.ground import (
    G_STANDARD,
    GroundMotion,
    mavroeidis_papageorgiou,
    one_sine,
    read_at2,
    read_csv,
    rectangular,
    ricker,
)

AT2 = """PEER NGA STRONG MOTION DATABASE RECORD
IMPERIAL VALLEY 10/15/79, EL CENTRO ARRAY #6, 230 (test excerpt)
ACCELERATION TIME SERIES IN UNITS OF G
NPTS=    7, DT=   .0050 SEC
  .1000000E-02  .2000000E-02 -.3000000E-02  .4000000E-02  .5000000E-02
 -.6000000E-02  .7000000E-02
"""


def test_read_at2(tmp_path):
    path = tmp_path / "RSN1_TEST.AT2"
    path.write_text(AT2)
    motion = read_at2(path)
    assert motion.time == pytest.approx(0.005 * np.arange(7))
    assert motion.acceleration[:, 0] == pytest.approx(
        G_STANDARD * np.array([1, 2, -3, 4, 5, -6, 7]) * 1e-3)
    assert not motion.acceleration[:, 1].any()


@pytest.mark.parametrize("edit, message", [
    (("NPTS=    7", "NPTS=    8"), "NPTS = 8 but the file has 7"),
    (("UNITS OF G", "UNITS OF FURLONGS"), "line 3: units not recognized"),
    (("NPTS=    7, DT=   .0050 SEC", "seven points"), "line 4: expected 'NPTS= n, DT= dt"),
    ((" .7000000E-02", " seven"), "line 6: not numbers"),
])
def test_bad_at2_files_are_named(tmp_path, edit, message):
    path = tmp_path / "bad.AT2"
    path.write_text(AT2.replace(*edit))
    with pytest.raises(sx.InputError, match=message):
        read_at2(path)


def test_read_csv_with_units(tmp_path):
    path = tmp_path / "record.csv"
    path.write_text("# units: g\ntime,acc\n0.0,0.0\n0.01,0.1\n\n0.02,-0.2\n")
    motion = read_csv(path)
    assert motion.acceleration[:, 0] == pytest.approx([0.0, 0.1 * G_STANDARD, -0.2 * G_STANDARD])
    assert read_csv(path, units="m/s^2").acceleration[2, 0] == pytest.approx(-0.2)


def test_bad_csv_files_are_named(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text("0.0 0.0\n0.01 0.1\n")
    with pytest.raises(sx.InputError, match="units unknown"):
        read_csv(path)
    path.write_text("# units: g\n0.0 0.0\n0.01 x\n")
    with pytest.raises(sx.InputError, match="line 3: not numbers"):
        read_csv(path)
    path.write_text("# units: g\n0.0 0.0\n0.0 0.1\n")
    with pytest.raises(sx.InputError, match="time must increase"):
        read_csv(path)
    with pytest.raises(sx.InputError, match="no ground-motion file"):
        read_csv(tmp_path / "absent.csv", units="g")


def test_pulses_have_their_closed_form_velocities():
    amplitude, period = 2.0, 0.5
    anti = one_sine(amplitude, period)
    assert anti.velocity()[-1, 0] == pytest.approx(0.0, abs=1e-6)  # a full cycle
    sym = one_sine(amplitude, period, symmetric=True)
    assert sym.velocity()[-1, 0] == pytest.approx(2 * amplitude * period / math.pi, rel=1e-6)
    assert ricker(amplitude, period).acceleration[:, 0].max() == pytest.approx(amplitude)
    assert rectangular(amplitude, period).velocity()[-1, 0] == pytest.approx(amplitude * period)
    # Mavroeidis-Papageorgiou: the acceleration integrates back to the closed-form velocity
    v_peak, tp, gamma, nu = 0.8, 1.2, 2.5, 0.3
    mp = mavroeidis_papageorgiou(v_peak, tp, gamma, nu)
    t = mp.time
    t0 = gamma * tp / 2
    x = 2 * math.pi * (t - t0) / tp
    closed = 0.5 * v_peak * (1 + np.cos(x / gamma)) * np.cos(x + nu)
    assert mp.velocity()[:, 0] == pytest.approx(closed - closed[0], abs=1e-5 * v_peak)


def test_baseline_correction_ends_at_rest_and_scaling_trimming():
    motion = GroundMotion(np.linspace(0, 2, 201), np.ones(201))
    corrected = motion.baseline_corrected()
    assert corrected.velocity()[-1] == pytest.approx([0.0, 0.0], abs=1e-12)
    assert motion.scaled(3.0).acceleration[5, 0] == 3.0
    trimmed = motion.trimmed(0.5, 1.0)
    assert trimmed.time[0] == 0.0 and trimmed.duration == pytest.approx(0.5)
    with pytest.raises(sx.InputError, match="nothing between"):
        motion.trimmed(5.0, 6.0)


def test_exact_velocity_between_samples():
    motion = GroundMotion([0.0, 1.0, 3.0], [0.0, 2.0, 0.0])
    assert motion.velocity_at(0.5) == pytest.approx([0.25, 0.0])  # int of 2t from 0 to 0.5
    assert motion.velocity_at(2.0) == pytest.approx([1.0 + 1.5, 0.0])
    assert motion.velocity_at(10.0) == pytest.approx([3.0, 0.0])
