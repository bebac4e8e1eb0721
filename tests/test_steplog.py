"""The step log keeps every report appended, in order, whether read between appends or not
(it writes its columns by batches: saxum.steplog)."""

import math

import numpy as np

from saxum.steplog import STEP_DTYPES, StepLog, StepReport


def _report(k: int) -> StepReport:
    return StepReport(step=k + 1, time=(k + 1) * 1e-3, iterations=k % 7, error=k * 1e-9,
                      converged=k % 5 != 0, contacts=30 + k % 3, active_contacts=k % 30,
                      max_interpenetration=k * 1e-12, kinetic_energy=0.5 * k,
                      projection_iterations=k % 2, solver=k % 5, natural_map=math.nan,
                      outcome=k % 4, rate=math.nan, bonds_lost=k % 3, damaged=k % 11)


def test_reports_kept_across_batches_and_reads():
    reports = [_report(k) for k in range(700)]  # past two batches and two growths
    log = StepLog()
    read_at = {0, 1, 255, 256, 257, 300, 511, 699}
    for k, r in enumerate(reports):
        log.append(r)
        assert len(log) == k + 1
        if k in read_at:  # a read between appends sees every report so far
            assert np.array_equal(log.step, np.arange(1, k + 2))
    for name, dtype in STEP_DTYPES.items():
        column = getattr(log, name)
        assert column.dtype == dtype and len(column) == len(reports)
        expected = np.array([getattr(r, name) for r in reports], dtype=dtype)
        # the values stored are the values appended (no arithmetic: nan where nan was given)
        assert np.array_equal(column, expected, equal_nan=column.dtype.kind == "f"), name
    assert log.summary().startswith("700 steps")
    assert np.array_equal(log.non_converged(), [r.step for r in reports if not r.converged])


def test_empty_log():
    log = StepLog()
    assert len(log) == 0 and log.summary() == "no steps" and log.step.size == 0
