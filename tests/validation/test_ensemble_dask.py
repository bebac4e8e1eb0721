"""The distributed path on a real local Dask cluster of 2 worker processes: a worker killed
(SIGKILL) while the ensemble runs; every run ends up in the file exactly once, none failed
(the scheduler runs the dead worker's tasks again elsewhere; the nanny restarts it)."""

import os
import signal

import pytest
from ensemble_case import write_scenario

from saxum import ensemble as ens
from saxum.scenario import load_scenario

pytest.importorskip("distributed")


def test_a_killed_worker_loses_no_run_and_duplicates_none(tmp_path):
    path = write_scenario(tmp_path)
    client = ens.connect(workers=2)
    try:
        pids = client.run(os.getpid)
        assert len(pids) == 2
        killed = []

        def kill_one(row):
            if not killed:  # after the first row: the other runs are queued or running
                victim = sorted(pids.values())[0]
                os.kill(victim, signal.SIGKILL)
                killed.append(victim)

        summary = ens.run_ensemble(load_scenario(path), tmp_path / "e.h5", client=client,
                                   quiet=True, on_row=kill_one)
        assert killed and killed[0] not in client.run(os.getpid).values()
    finally:
        cluster = client.cluster
        client.close()
        cluster.close()
    runs = ens.read_ensemble(tmp_path / "e.h5").runs
    keys = sorted(zip(runs["record"].tolist(), runs["scale"].tolist(), strict=True))
    assert keys == [(k, s) for k in range(2) for s in (1.0, 2.0, 3.0)]
    assert summary.failed == 0 and (runs["collapsed"] >= 0).all(), runs["error"]
