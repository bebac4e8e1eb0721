"""The "no contact" law: NO_CONTACT in Python, kind = "none" in scenarios (the free fall
through each other is in tests/validation/test_no_contact_free_fall.py)."""

import json
import textwrap

import numpy as np
import pytest

import saxum as sx
from saxum.detection import detector_for
from saxum.scenario import parse_scenario
from saxum.structures.solid import extruded

BLOCKS = {"blocks": [
    {"vertices": [[-1, -0.1], [1, -0.1], [1, 0], [-1, 0]], "kind": "fixed", "group": "ground"},
    {"vertices": [[0, 0], [0.2, 0], [0.2, 0.2], [0, 0.2]], "group": "stone", "density": 2000},
    {"vertices": [[0.2, 0], [0.4, 0], [0.4, 0.2], [0.2, 0.2]], "group": "ghost",
     "density": 2000}]}


def _scenario(tmp_path, laws):
    (tmp_path / "blocks.json").write_text(json.dumps(BLOCKS))
    text = ('[structure]\ntype = "blocks"\nfile = "blocks.json"\n' + textwrap.dedent(laws)
            + "\n[output]\nduration = 0.01\n")
    return parse_scenario(text, base_dir=tmp_path)


def _groups(model, a, b):
    return model.group_law[model.group_names.index(a), model.group_names.index(b)]


def test_kind_none_gives_no_law_and_no_contacts(tmp_path):
    model = _scenario(tmp_path, """\
        [[laws]]
        groups = ["*", "*"]
        friction = 0.6
        [[laws]]
        groups = ["ghost", "*"]
        kind = "none"
        [[laws]]
        groups = ["ghost", "ground"]
        friction = 0.5
        """).build_model()
    assert _groups(model, "ghost", "stone") == -1 and _groups(model, "ghost", "ghost") == -1
    # the given coefficients, read from TOML and stored: 1e-15 allows only a different float
    assert model.laws[_groups(model, "ghost", "ground")].friction == pytest.approx(
        0.5, rel=1e-15)  # exact pair wins
    assert model.laws[_groups(model, "stone", "ground")].friction == pytest.approx(0.6, rel=1e-15)
    contacts = detector_for(model).contacts_at(model.body_q0)
    n = contacts.count
    pairs = {frozenset((int(c), int(a))) for c, a in
             zip(contacts.candidate[:n], contacts.antagonist[:n], strict=True)}
    # the ghost touches the stone side to side, and both stand on the ground
    assert pairs == {frozenset((0, 1)), frozenset((0, 2))}


def test_extruded_model_keeps_no_contact():
    b = sx.ModelBuilder()
    b.add_block([(-1, -0.1), (1, -0.1), (1, 0), (-1, 0)], kind=sx.BodyKind.FIXED, group="ground")
    b.add_block([(0, 0), (0.2, 0), (0.2, 0.2), (0, 0.2)], density=2000.0)
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    b.set_law("block", "ground", sx.NO_CONTACT)
    model = extruded(b.finalize(), 0.2)
    assert model.dim == 3 and _groups(model, "block", "ground") == -1
    assert detector_for(model).contacts_at(model.body_q0).count == 0
    # the given coefficient copied into the 3D model: 1e-15 allows only a different float
    assert np.allclose(model.law_friction, 0.6, rtol=1e-15, atol=0.0)


@pytest.mark.parametrize("laws, expected", [
    ('[[laws]]\ngroups = ["*", "*"]\nkind = "none"\nfriction = 0.6',
     ['laws[0]', 'kind = "none" (no contact) takes no parameters; drop friction']),
    ('[[laws]]\ngroups = ["*", "*"]', ['laws[0]', "friction is required", 'kind = "none"']),
    ('[[laws]]\ngroups = ["stone", "*"]\nfriction = 0.6',
     ["no contact law between groups 'ghost' and 'ghost'", "NO_CONTACT"]),
])
def test_bad_laws_name_the_key(tmp_path, laws, expected):
    with pytest.raises(sx.InputError) as info:
        _scenario(tmp_path, laws).build_model()
    for text in expected:
        assert text in str(info.value)


def test_set_law_refuses_what_is_not_a_law():
    b = sx.ModelBuilder()
    with pytest.raises(sx.InputError, match="must be a ContactLaw or NO_CONTACT, got 'none'"):
        b.set_law("a", "b", "none")
