"""Ground motion: readers (PEER .AT2, CSV), pulses, baseline correction, bad files."""

import math

import numpy as np
import pytest

import saxum as sx
from saxum.ground import (
    G_STANDARD,
    GroundMotion,
    harmonic,
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
    (("NPTS=    7", "NPTS=    8"), "line 4: the header says NPTS = 8 but lines 5-6 hold 7"),
    (("DT=   .0050", "DT=   -.0050"), "line 4: the time step DT must be > 0"),
    ((" .7000000E-02", " NaN"), "line 6: NaN or infinite value"),
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


@pytest.mark.parametrize("text, message", [
    ("0.0 0.0\n0.01 0.1\n", "units unknown"),
    ("# units: g\n0.0 0.0\n0.01 x\n", "line 3: not numbers"),
    ("# units: g\n\n0.0 0.0\n0.01 0.1\n0.01 0.2\n",
     "line 5: time must increase: 0.01 s follows 0.01 s \\(line 4\\)"),
    ("# units: g\n0.0 0.0\n0.02 0.1\n0.01 0.2\n", "line 4: time must increase"),
    ("# units: g\nt,a\n0.0,0.0\n,0.1\n", "line 4: a value is missing"),
    ("# units: g\n0.0 0.0\n0.1\n", "line 3: expected 2 columns"),
    ("# units: g\n0.0 0.0\n0.01 nan\n", "line 3: NaN or infinite value"),
    ("# units: furlongs\n0.0 0.0\n0.01 0.1\n", "line 1: units 'furlongs' not one of"),
    ("# units: g\n# dt: 0.01\n0.0 0.0\n0.01 0.1\n0.025 0.1\n",
     "line 5: the time step 0.015 s does not match dt = 0.01 s stated on line 2"),
    ("# units: g\n# dt: fast\n0.0 0.0\n0.01 0.1\n", "line 2: the time step must be"),
])
def test_bad_csv_files_name_the_line(tmp_path, text, message):
    path = tmp_path / "r.csv"
    path.write_text(text)
    with pytest.raises(sx.InputError, match=message):
        read_csv(path)


def test_csv_stated_time_step_and_missing_file(tmp_path):
    path = tmp_path / "r.csv"
    path.write_text("# units: m/s^2\n# dt: 0.01\n0.0 0.0\n0.01 0.1\n0.02 0.2\n")
    assert read_csv(path).time == pytest.approx([0.0, 0.01, 0.02])
    with pytest.raises(sx.InputError, match="no ground-motion file"):
        read_csv(tmp_path / "absent.csv", units="g")


def test_harmonic_motion_with_a_ramp():
    amplitude, period, cycles = 2.0, 0.4, 5
    steady = harmonic(amplitude, period, cycles)
    assert steady.duration == pytest.approx(cycles * period)
    assert np.abs(steady.acceleration[:, 0]).max() == pytest.approx(amplitude, rel=1e-3)
    assert steady.velocity()[-1, 0] == pytest.approx(0.0, abs=1e-4)  # whole cycles
    ramped = harmonic(amplitude, period, cycles, ramp=cycles * period)
    t, a = ramped.time, ramped.acceleration[:, 0]
    # the envelope grows linearly: the peak of each cycle is A t/t_r at its peak time
    for k in range(cycles):
        peak = (k + 0.25) * period
        assert ramped.acceleration_at(peak)[0] == pytest.approx(
            amplitude * peak / (cycles * period), rel=1e-3)
    assert abs(a[t < period]).max() < 0.25 * amplitude
    with pytest.raises(sx.InputError, match="cycles must be > 0"):
        harmonic(1.0, 1.0, 0)
    with pytest.raises(sx.InputError, match="ramp must be >= 0"):
        harmonic(1.0, 1.0, 2, ramp=-1.0)


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
