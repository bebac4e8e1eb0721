"""The _g0 laws' state (ContactLaw.initial_gap, saxum.laws): carried by contact key, in
checkpoints (a restart from one steps on bit for bit), the scenario key, bad input."""

from pathlib import Path

import numpy as np
import pytest

from saxum import ContactLaw, LawKind
from saxum.contacts import Contacts
from saxum.errors import InputError
from saxum.lmgc90 import import_lmgc90
from saxum.results import Results
from saxum.runner import run_scenario
from saxum.scenario import load_scenario, parse_scenario

ARCH_2D = Path(__file__).parent / "data" / "lmgc90" / "arch2d"
ARCH = Path(__file__).parents[1] / "examples" / "arch.toml"


def test_initial_gap_is_carried_by_contact_key():
    old, new = Contacts(2, 4), Contacts(2, 4)
    old.count, new.count = 2, 3
    old.key[:2] = (5, 9)
    old.initial_gap[:2] = (0.01, 0.02)
    new.key[:3] = (3, 5, 9)
    new.initial_gap[:3] = 7.0  # stale rows of an earlier step
    assert new.warm_start_from(old) == 2
    # copied where the key persists, reset where the contact is new (exact: copies and a
    # reset, no arithmetic)
    np.testing.assert_array_equal(new.initial_gap[1:3], old.initial_gap[:2])
    assert abs(new.initial_gap[0]) <= 1e-15  # a reset to zero (the bound only guards it)
    np.testing.assert_array_equal(new.copy().initial_gap[:3], new.initial_gap[:3])


@pytest.mark.parametrize("kind", [LawKind.RESTITUTION_COULOMB, LawKind.COHESIVE])
def test_initial_gap_only_for_the_signorini_laws(kind):
    extra = {"k_n": 1e9, "k_t": 1e9, "f_t": 1e5, "cohesion": 1e5, "g_i": 10.0,
             "g_ii": 10.0} if kind == LawKind.COHESIVE else {}
    with pytest.raises(InputError, match="mortar.*initial_gap.*signorini_coulomb"):
        ContactLaw(friction=0.5, kind=kind, initial_gap=True, name="mortar", **extra)


def test_scenario_key():
    text = ARCH.read_text(encoding="utf-8").replace(
        'groups = ["voussoir", "voussoir"]\n',
        'groups = ["voussoir", "voussoir"]\nkind = "signorini_coulomb"\ninitial_gap = true\n')
    model = parse_scenario(text).build_model()
    voussoir, support = (model.group_names.index(g) for g in ("voussoir", "support"))
    assert model.laws[model.group_law[voussoir, voussoir]].initial_gap
    assert not model.laws[model.group_law[voussoir, support]].initial_gap
    assert model.law_initial_gap.tolist().count(True) == 1
    with pytest.raises(InputError, match="initial_gap"):
        parse_scenario(text.replace('kind = "signorini_coulomb"',
                                    'kind = "restitution_coulomb"')).build_model()


def test_checkpoint_keeps_initial_gaps_and_restarts_bit_for_bit(tmp_path):
    """LMGC90's arch (joints open, IQS_CLB_g0) run for 0.1 s with a checkpoint at 0.05 s:
    restarted from it, the run ends where the run in one go ended, bit for bit; without the
    checkpoint's initial gaps it does not (its open joints no longer act as closed)."""
    imported = import_lmgc90(ARCH_2D)
    scenario = tmp_path / "arch.toml"
    imported.write_scenario(scenario, duration=0.1)
    with scenario.open("a", encoding="utf-8") as f:
        f.write("interval = 0.05\ncheckpoint_interval = 0.05\n")
    results = tmp_path / "arch.h5"
    assert run_scenario(load_scenario(scenario), results, quiet=True).status == "finished"
    with Results(results) as r:
        assert r.checkpoint_steps.tolist() == [0, 50, 100]
        saved = r.checkpoint(1)
        end = r.body_q[-1]
    assert saved["contacts"]["initial_gap"].max() > 0.02  # the extrados joints, 3.1 cm
    ends = []
    for kept in (True, False):
        if not kept:
            saved["contacts"]["initial_gap"] = np.zeros(len(saved["contacts"]["key"]))
        sim = load_scenario(scenario).build_simulation()
        state = sim.restore(saved)
        sim.run(state, 0.05)
        assert state.step == 100
        ends.append(state.body_q)
    assert np.array_equal(ends[0], end)
    assert not np.allclose(ends[1], end, rtol=0.0, atol=1e-3)  # the crown falls mm
