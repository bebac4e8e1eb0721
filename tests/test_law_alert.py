"""Alert distance per law (ContactLaw.alert, scenario [[laws]] alert): the detector makes
contacts of a pair of groups within its law's alert, and the others within its own."""

import json

import numpy as np
import pytest

import saxum as sx
from saxum.detection import detector_for
from saxum.scenario import parse_scenario
from saxum.structures.solid import box

SIDE = 0.2  # [m]: the detector's default alert is 2 % of it, 4 mm


def _model(dim, lift, alert):
    """A free block `lift` [m] above a fixed one, law alert `alert` [m] (None: default)."""
    if dim == 2:
        b = sx.ModelBuilder()
        b.add_block([(-1, -0.1), (1, -0.1), (1, 0), (-1, 0)], kind=sx.BodyKind.FIXED,
                    group="ground")
        b.add_block([(0, lift), (SIDE, lift), (SIDE, lift + SIDE), (0, lift + SIDE)],
                    density=2000.0)
    else:
        b = sx.ModelBuilder(dim=3)
        b.add_block(box(-1, -1, -0.1, 1, 1, 0), kind=sx.BodyKind.FIXED, group="ground")
        b.add_block(box(0, 0, lift, SIDE, SIDE, lift + SIDE), density=2000.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6, alert=alert))
    return b.finalize()


def _count(model):
    return detector_for(model).contacts_at(model.body_q0).count


@pytest.mark.parametrize("dim, corners", [(2, 2), (3, 4)])
def test_the_law_alert_decides_which_pairs_are_contacts(dim, corners):
    assert _count(_model(dim, 0.010, None)) == 0  # 10 mm gap, beyond the default 4 mm
    assert _count(_model(dim, 0.010, 0.02)) == corners  # within the law's 20 mm
    assert _count(_model(dim, 0.002, None)) == corners  # 2 mm, within the default
    assert _count(_model(dim, 0.002, 0.001)) == 0  # beyond the law's 1 mm


@pytest.mark.parametrize("dim", [2, 3])
def test_a_law_alert_equal_to_the_default_changes_nothing(dim):
    plain, given = _model(dim, 0.002, None), _model(dim, 0.002, 0.02 * SIDE)
    a, b = (detector_for(m).contacts_at(m.body_q0) for m in (plain, given))
    assert a.count == b.count > 0
    for name in ("candidate", "antagonist", "key", "gap", "area"):
        np.testing.assert_array_equal(getattr(a, name)[:a.count], getattr(b, name)[:b.count])


def test_scenario_alert_per_law(tmp_path):
    (tmp_path / "blocks.json").write_text(json.dumps({"blocks": [
        {"vertices": [[-1, -0.1], [1, -0.1], [1, 0], [-1, 0]], "kind": "fixed",
         "group": "ground"},
        {"vertices": [[0, 0.01], [SIDE, 0.01], [SIDE, 0.21], [0, 0.21]], "density": 2000}]}))
    text = ('[structure]\ntype = "blocks"\nfile = "blocks.json"\n'
            '[[laws]]\ngroups = ["block", "block"]\nfriction = 0.6\n'
            '[[laws]]\ngroups = ["block", "ground"]\nfriction = 0.6\nALERT\n'
            "[output]\nduration = 0.01\n")
    model = parse_scenario(text.replace("ALERT", "alert = 0.02"), base_dir=tmp_path).build_model()
    # the given alert, stored: 1e-15 allows only a different float
    assert model.laws[model.group_law[0, 1]].alert == pytest.approx(0.02, rel=1e-15)
    assert _count(model) == 2
    for bad, expected in (("alert = -0.01", "laws[1].alert"),
                          ('kind = "none"\nalert = 0.02', "drop alert")):
        with pytest.raises(sx.InputError, match=expected.replace("[", r"\[")):
            parse_scenario(text.replace("friction = 0.6\nALERT", bad), base_dir=tmp_path)


@pytest.mark.parametrize("alert", [-0.01, 0.0, float("nan"), float("inf")])
def test_bad_alert_names_the_key(alert):
    with pytest.raises(sx.InputError, match="alert must be a finite length > 0"):
        sx.ContactLaw(friction=0.6, alert=alert)


def _pebble_and_stone(lift):
    """A 0.05 m pebble and a 0.2 m stone, each `lift` [m] above a fixed ground."""
    b = sx.ModelBuilder()
    b.add_block([(-1, -0.1), (1, -0.1), (1, 0), (-1, 0)], kind=sx.BodyKind.FIXED,
                group="ground")
    b.add_block([(-0.5, lift), (-0.45, lift), (-0.45, lift + 0.05), (-0.5, lift + 0.05)],
                density=2000.0)
    b.add_block([(0, lift), (SIDE, lift), (SIDE, lift + SIDE), (0, lift + SIDE)],
                density=2000.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    return b.finalize()


def test_per_pair_takes_the_alert_from_the_smaller_block_of_each_pair():
    # 2 mm gaps: beyond the pebble's 2 % (1 mm), within the stone's (4 mm)
    model = _pebble_and_stone(0.002)
    plain = detector_for(model).contacts_at(model.body_q0)
    paired = detector_for(model, sx.DetectionSettings(per_pair=True)).contacts_at(model.body_q0)
    assert plain.count == 0  # the model's alert: 2 % of the pebble, 1 mm
    assert paired.count == 2 and set(paired.candidate[:2]) | set(paired.antagonist[:2]) == {0, 2}
