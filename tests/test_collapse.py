"""The settlement criterion of saxum.collapse: blocks carried by a settling support are not a
collapse; a block thrown or still moving once the support has stopped is."""

import math

import saxum as sx
from saxum.collapse import CollapseCriterion, run_trial


def _block_on_a_settling_support(settlement, time=0.2, width=0.4):
    """A block `width` wide whose left edge is at the edge x = 0 between a fixed support
    (left) and a support that settles by `settlement` [m] in `time` [s] at a constant rate."""
    b = sx.ModelBuilder()
    b.add_block([(-1, -0.1), (0, -0.1), (0, 0), (-1, 0)], kind=sx.BodyKind.FIXED,
                group="ground", name="fixed")
    b.add_block([(0, -0.1), (1, -0.1), (1, 0), (0, 0)], kind=sx.BodyKind.FIXED,
                group="ground", name="settling")
    b.add_block([(0, 0), (width, 0), (width, 0.2), (0, 0.2)], density=2000.0, name="block")
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    b.drive("settling", lambda t: (0.0, -settlement / time, 0.0) if t < time
            else (0.0, 0.0, 0.0))
    return sx.Simulation(b.finalize(), dt=1e-3)


def test_a_block_carried_by_a_settling_support_is_not_a_collapse():
    criterion = CollapseCriterion(after_motion=True, not_before=0.2)
    trial = run_trial(_block_on_a_settling_support(0.02), 0.02, criterion)
    assert not trial.collapsed and trial.displacement < 1e-6  # moved after the support stopped
    q, q0 = trial.state.body_q, trial.simulation.model.body_q0
    assert math.isclose(q[2, 1] - q0[2, 1], q[1, 1] - q0[1, 1], rel_tol=1e-6)  # as the support
    assert math.isclose(q[1, 1] - q0[1, 1], -0.02, rel_tol=0.01)
    # from the initial position, the same motion looks like a collapse
    assert run_trial(_block_on_a_settling_support(0.02), 0.02, CollapseCriterion()).collapsed


def test_a_block_thrown_during_the_settlement_is_a_collapse():
    """A support that drops 20 cm in 0.1 s leaves the block behind: it falls freely, and
    moves as fast as after a fall by the threshold (1 % of its size) long before the end."""
    criterion = CollapseCriterion(after_motion=True, not_before=0.1)
    trial = run_trial(_block_on_a_settling_support(0.2, time=0.1), 0.2, criterion)
    assert trial.collapsed and trial.time < 0.1


SLIDE = """\
[structure]
type = "blocks"
file = "block.json"
[[laws]]
groups = ["block", "ground"]
friction = 0.5
[[laws]]
groups = ["block", "block"]
friction = 0.5
[loads]
load_factor_rate = 0.25
[solver]
dt = 1e-3
[output]
duration = 3.2
interval = 0.05
"""


def test_a_slow_slide_begins_where_the_block_starts_to_slide(tmp_path, capsys):
    """A flat block (1 x 0.2 m: it slides long before it could tip, at a/g = 5) under a
    horizontal load growing as a(t) = 0.25 g t on a joint of friction 0.5 starts to slide at
    t = 0.5 / 0.25 = 2 s (Coulomb) and moves as g (0.25 t - 0.5)^3 / 6 after: 4.5 cm, a fifth
    of the collapse displacement, only at 2.5 s. The collapsing motion began at the first
    output frame after 2 s (frames every 0.05 s), with the joint sliding and no hinge."""
    from saxum.cli import main
    from saxum.collapse import find_collapse
    from saxum.results import Results

    (tmp_path / "block.json").write_text(
        '{"blocks": [{"vertices": [[-5, -0.2], [5, -0.2], [5, 0], [-5, 0]], "kind": "fixed",'
        ' "group": "ground", "name": "ground"},'
        ' {"vertices": [[0, 0], [1, 0], [1, 0.2], [0, 0.2]], "density": 2000, "name": "slab"}]}')
    scenario = tmp_path / "slide.toml"
    scenario.write_text(SLIDE)
    assert main(["run", str(scenario), "--quiet"]) == 0
    with Results(scenario.with_suffix(".h5")) as r:
        event = find_collapse(r)
        began = float(r.time[event.onset_frame])
    assert event is not None and event.block == "slab"
    assert 2.0 < began <= 2.05 + 1e-9
    assert main(["info", str(scenario.with_suffix(".h5"))]) == 0
    out = capsys.readouterr().out
    assert f"when the collapsing motion began, t = {began:.4g} s" in out
    assert "sliding joint between ground and slab" in out and "hinge between" not in out
