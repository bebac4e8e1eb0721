"""The joint laws (saxum.laws ELASTIC, VISCOUS_COULOMB, COHESIVE) in the one NLGS: dry laws
untouched bit for bit, the joint state carried by contact identity and never healing, the
scenario keys and their errors, and a resumed run with damage bit for bit."""

import math
import os
import signal
import textwrap

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st
from results_check import same_results

import saxum as sx
from saxum.contacts import Contacts
from saxum.runner import resume_run, run_scenario
from saxum.scenario import parse_scenario
from saxum.solver.laws_local import _damage
from saxum.structures.wall import add_grounded_running_bond_wall

COHESIVE = dict(kind=sx.LawKind.COHESIVE, k_n=1e10, k_t=1e10, f_t=1e5, cohesion=2e5, g_i=10.0,
                g_ii=20.0)


def _dry_wall(dim: int) -> sx.Model:
    """A small wall under a horizontal load: sliding, rocking and impacts."""
    if dim == 2:
        b = sx.ModelBuilder(gravity=(7.0, -9.81))
        add_grounded_running_bond_wall(b, courses=4, bricks=3)
        groups = ("brick", "ground")
    else:
        b = sx.ModelBuilder(dim=3, gravity=(7.0, 0.0, -9.81))
        for k in range(3):
            x, z = 0.05 * k, 0.2 * k
            b.add_block([(x + i, j, z + c) for i in (0, 0.3) for j in (0, 0.2) for c in (0, 0.2)],
                        density=2000.0)
        b.add_block([(i, j, k) for i in (-1, 2) for j in (-1, 1) for k in (-0.2, 0)],
                    kind=sx.BodyKind.FIXED, group="ground")
        groups = ("block", "ground")
    law = sx.ContactLaw(friction=0.5)
    for pair in ((groups[0], groups[0]), groups):
        b.set_law(*pair, law)
    return b.finalize()


@pytest.mark.parametrize("dim", [2, 3])
def test_dry_laws_are_bit_identical_through_the_joint_law_path(dim):
    """The joint-law hook (law_terms, then the flagged sweep) leaves dry contacts as they
    were: a run that fills law_map for its dry contacts equals the run that does not."""
    model = _dry_wall(dim)
    runs = []
    for joints in (False, True):
        sim = sx.Simulation(model, dt=1e-3, solver=sx.NLGS(rest_after=0))
        sim.problem.joint_laws = joints
        state = sim.initial_state()
        impulses = []
        for _ in range(150):
            sim.step(state)
            impulses.append(state.contacts.impulse[: state.contacts.count].copy())
        runs.append((state.body_q.copy(), state.body_v.copy(), impulses, sim.log.iterations))
    (q0, v0, r0, it0), (q1, v1, r1, it1) = runs
    assert np.array_equal(q0, q1) and np.array_equal(v0, v1)
    assert np.array_equal(it0, it1) and all(np.array_equal(a, b) for a, b in zip(r0, r1,
                                                                             strict=True))
    assert np.abs(q0 - model.body_q0).max() > 1e-3  # the wall did move


@given(st.lists(st.tuples(st.floats(-1e-3, 1e-3), st.floats(0.0, 1e-3)), min_size=1,
                max_size=30))
def test_damage_never_decreases(path):
    """Any path of openings (negative: closed) and tangential jumps [m]."""
    p = sx.ContactLaw(friction=0.6, **COHESIVE).parameters
    damage, history = np.zeros(1), np.zeros(1)
    for opening, jump in path:
        before, kappa = damage[0], history[0]
        _damage(p, max(opening, 0.0), jump, damage, history, 0)
        assert before <= damage[0] <= 1.0 and kappa <= history[0]


def test_carry_keeps_the_state_by_key_and_new_cohesive_contacts_start_cracked():
    law_kind = np.array([sx.LawKind.GAP_SIGNORINI_COULOMB, sx.LawKind.COHESIVE], np.int8)
    old = Contacts(2)
    old.count = 3
    old.key[:3] = (10, 20, 30)
    old.damage[:3] = (0.0, 0.25, 0.5)
    old.history[:3] = (0.5, 1.5, 2.5)
    old.crush[:3] = (1e-5, 2e-5, 3e-5)
    old.slip[:3, 0] = (1e-6, 2e-6, 3e-6)
    old.impulse[:3] = 1.0
    new = Contacts(2)
    new.count = 4
    new.key[:4] = (5, 20, 25, 30)
    new.law[:4] = (1, 1, 0, 1)
    new.damage[:4] = 0.75  # what a reused row held before
    assert new.warm_start_from(old, law_kind) == 2
    assert new.damage[:4].tolist() == [1.0, 0.25, 0.0, 0.5]
    assert new.history[:4].tolist() == [0.0, 1.5, 0.0, 2.5]
    assert new.crush[:4].tolist() == [0.0, 2e-5, 0.0, 3e-5]
    assert new.slip[:4, 0].tolist() == [0.0, 2e-6, 0.0, 3e-6]
    assert new.impulse[:4, 0].tolist() == [0.0, 1.0, 0.0, 1.0]


def test_joints_closed_at_the_start_are_bonded_and_open_ones_are_not():
    b = sx.ModelBuilder()
    b.add_block([(-1, -0.2), (2, -0.2), (2, 0), (-1, 0)], kind=sx.BodyKind.FIXED,
                group="ground")
    b.add_block([(0, 0), (0.2, 0), (0.2, 0.2), (0, 0.2)], density=2000.0)
    b.add_block([(0.5, 1e-4), (0.7, 1e-4), (0.7, 0.2), (0.5, 0.2)], density=2000.0)
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6, **COHESIVE))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    sim = sx.Simulation(b.finalize(), dt=1e-4)
    state = sim.initial_state()
    c = state.contacts
    assert c.count == 4
    touching = (c.candidate[:4] == 1) | (c.antagonist[:4] == 1)
    assert c.damage[:4][touching].tolist() == [0.0, 0.0]
    assert c.damage[:4][~touching].tolist() == [1.0, 1.0]  # 0.1 mm apart
    sim.step(state)
    assert state.contacts.count == 4 and np.array_equal(state.contacts.damage[:4], c.damage[:4])


WALL = textwrap.dedent("""\
    title = "mortared wall"
    [structure]
    type = "running_bond_wall"
    courses = 3
    bricks = 3
    [[laws]]
    groups = ["*", "*"]
    friction = 0.6
    kind = "cohesive"
    k_n = 1e10
    k_t = 1e10
    f_t = 1e3
    cohesion = 2e3
    g_i = 1.0
    g_ii = 2.0
    [loads]
    load_factor_rate = 5.0
    [output]
    duration = 0.3
    interval = 0.01
    checkpoint_interval = 0.05
    [solver]
    dt = 2e-4
""")


def test_resume_with_damage_is_bit_for_bit(tmp_path, monkeypatch):
    """The wall's joints start to crack at ~0.24 s; the run is stopped at 0.26 s and resumed
    from its checkpoint at 0.25 s, with some joints partly damaged."""
    one_go = tmp_path / "one.h5"
    assert run_scenario(parse_scenario(WALL), one_go, quiet=True).status == "finished"
    from saxum.cli import info_text
    from saxum.results import Results
    with Results(one_go) as r:
        k = np.searchsorted(r.time, 0.25 - 1e-9)
        damage = r.contacts(k)["damage"]
        assert 0.0 < damage.max() < 1.0  # cracking at the checkpoint
        assert r.contacts(r.frame_count - 1)["damage"].max() == 1.0
        lost = r.steps["bonds_lost"]
        first = r.steps["step"][np.flatnonzero(lost)[0]]
        assert r.steps["damaged"].max() > 0 and lost.sum() > 0
        assert (f"cohesive joints: {lost.sum()} bond(s) cracked (first at step {first}) over "
                "the run") in info_text(r)
    _stop_resume_and_compare(WALL, one_go, tmp_path, monkeypatch)


def _stop_resume_and_compare(text, one_go, tmp_path, monkeypatch):
    """Run `text` again, stopped at step 1300 (0.26 s), resume it from its checkpoint at
    0.25 s and compare it with the run in one go, bit for bit."""
    from saxum.results import ResultsWriter
    stopped = tmp_path / "stopped.h5"
    original = ResultsWriter.log_step

    def log_step(self, report):
        original(self, report)
        if report.step == 1300:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(ResultsWriter, "log_step", log_step)
    assert run_scenario(parse_scenario(text), stopped, quiet=True).status == "interrupted"
    monkeypatch.setattr(ResultsWriter, "log_step", original)
    assert resume_run(stopped, quiet=True).status == "finished"
    same_results(stopped, one_go)


def test_resume_with_crushing_is_bit_for_bit(tmp_path, monkeypatch):
    """The wall with a cap (f_c = 15 kPa, C_ss = 9): its toes crush from ~0.21 s, so the
    checkpoint at 0.25 s holds crushed points (Contacts.crush > 0) that keep crushing."""
    text = WALL.replace("g_ii = 2.0\n", "g_ii = 2.0\nf_c = 1.5e4\ng_fc = 1.0\nc_ss = 9.0\n")
    one_go = tmp_path / "one.h5"
    assert run_scenario(parse_scenario(text), one_go, quiet=True).status == "finished"
    from saxum.results import Results
    with Results(one_go) as r:
        k = np.searchsorted(r.time, 0.25 - 1e-9)
        crush = r.contacts(k)["crush"]
        assert crush.max() > 0.0
        assert r.contacts(r.frame_count - 1)["crush"].max() > crush.max()
    _stop_resume_and_compare(text, one_go, tmp_path, monkeypatch)


# --- bad input --------------------------------------------------------------------------------


def _wall_with(law: str) -> str:
    return WALL.replace('kind = "cohesive"\n', law + "\n").replace("k_n = 1e10\n", "", 1)


@pytest.mark.parametrize(("line", "words"), [
    ('kind = "cohesive"\nk_n = -1e10', "k_n"),
    ('kind = "cohesive"\nk_n = 1e10\ng_i = -1.0', "g_i"),
    ('kind = "cohesive"\nk_n = 1e10\nf_t = -1e3', "f_t"),
    ('kind = "cohesive"\nk_n = 1e10\ncohesion = -2e3', "cohesion"),
    ('kind = "cohesive"\nk_n = 1e10\nk_t = -1e10', "k_t"),
])
def test_negative_parameters_name_the_key(line, words):
    text = _wall_with(line)
    for key in ("g_i", "f_t", "cohesion", "k_t"):
        if f"\n{key} = -" in line:
            # the wall's own (positive) value of that key would be a duplicate TOML key
            text = "\n".join(row for row in text.split("\n")
                              if not (row.startswith(f"{key} = ") and "-" not in row))
    with pytest.raises(sx.InputError, match=words) as info:
        parse_scenario(text)
    assert "laws" in str(info.value)


@pytest.mark.parametrize(("given", "least"), [
    # f_t^2 / (2 k_n) = 1e6 / 2e10
    (("g_i = 1.0", "g_i = 1e-5"), "g_i >= f_t^2 / (2 k_n) = 5e-05 J/m^2"),
    # cohesion^2 / (2 k_t) = 4e6 / 2e10
    (("g_ii = 2.0", "g_ii = 1e-4"), "g_ii >= cohesion^2 / (2 k_t) = 0.0002 J/m^2"),
])
def test_snap_back_names_the_law_and_the_least_fracture_energy(given, least):
    with pytest.raises(sx.InputError) as info:
        parse_scenario(WALL.replace(*given)).build_model()
    message = str(info.value)
    assert "laws[0]" in message and least.split(" >=")[0] in message and "snap back" in message
    assert least in message


def test_a_parameter_of_another_kind_and_a_missing_one_are_named():
    with pytest.raises(sx.InputError, match="eta is not a parameter of kind COHESIVE"):
        sx.ContactLaw(friction=0.6, eta=1.0, **COHESIVE)
    with pytest.raises(sx.InputError, match="kind ELASTIC needs k_n > 0"):
        sx.ContactLaw(friction=0.6, kind=sx.LawKind.ELASTIC)


def test_bad_cap_hardening_is_named():
    """kappa_p (the cap's hardening, saxum.laws) needs the cap, and is a length >= 0."""
    with pytest.raises(sx.InputError, match="kappa_p = 0.001 m .* needs f_c and g_fc"):
        sx.ContactLaw(friction=0.6, kappa_p=1e-3, **COHESIVE)
    with pytest.raises(sx.InputError, match="kappa_p must be a finite number >= 0"):
        sx.ContactLaw(friction=0.6, kappa_p=-1e-3, f_c=1e6, g_fc=500.0, **COHESIVE)
    with pytest.raises(sx.InputError, match="kappa_p must be a finite number >= 0"):
        sx.ContactLaw(friction=0.6, kappa_p=math.nan, f_c=1e6, g_fc=500.0, **COHESIVE)
    with pytest.raises(sx.InputError, match="kappa_p is not a parameter of kind ELASTIC"):
        sx.ContactLaw(friction=0.6, kind=sx.LawKind.ELASTIC, k_n=1e10, kappa_p=1e-3)
    text = WALL.replace("g_ii = 2.0\n", "g_ii = 2.0\nkappa_p = -1e-3\n")
    with pytest.raises(sx.InputError, match="kappa_p"):
        parse_scenario(text)


def test_a_cohesive_law_for_groups_that_never_touch_is_an_error():
    b = sx.ModelBuilder()
    b.add_block([(-1, -0.2), (2, -0.2), (2, 0), (-1, 0)], kind=sx.BodyKind.FIXED,
                group="ground")
    b.add_block([(0, 0), (0.2, 0), (0.2, 0.2), (0, 0.2)], density=2000.0)
    b.add_block([(0.5, 0), (0.7, 0), (0.7, 0.2), (0.5, 0.2)], density=2000.0, group="far")
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("far", "ground", sx.ContactLaw(friction=0.6))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    b.set_law("far", "far", sx.ContactLaw(friction=0.6))
    b.set_law("block", "far", sx.ContactLaw(friction=0.6, name="laws[3]", **COHESIVE))
    with pytest.raises(sx.InputError, match=r"laws\[3\].*\(block, far\).*`groups`"):
        sx.Simulation(b.finalize(), dt=1e-4).initial_state()


def test_joint_laws_need_nlgs():
    """The hybrid (the default solver) is refused when asked for, and not the default, for a
    model with joint laws."""
    text = WALL.replace("dt = 2e-4", 'dt = 2e-4\nkind = "hybrid"')
    with pytest.raises(sx.InputError, match="NLGS"):
        parse_scenario(text).build_simulation()
    assert type(parse_scenario(WALL).build_simulation().solver) is sx.NLGS
    model = parse_scenario(WALL).build_model()
    assert type(sx.Simulation(model, dt=1e-4).solver) is sx.NLGS
    with pytest.raises(sx.InputError, match="NLGS only, not by Hybrid"):
        sx.Simulation(model, dt=1e-4, solver=sx.Hybrid())


def test_fclib_export_refuses_joint_laws():
    from saxum.fclib import step_problem
    sim = parse_scenario(WALL).build_simulation()
    state = sim.initial_state()
    sim.step(state)
    with pytest.raises(sx.InputError, match="joint laws"):
        step_problem(sim, state)


def test_paraview_contacts_carry_damage(tmp_path):
    import meshio

    from saxum.results import Results
    from saxum.vtk import export_vtk

    out = tmp_path / "wall.h5"
    text = WALL.replace("duration = 0.3", "duration = 0.28").replace("interval = 0.01",
                                                                     "interval = 0.14")
    run_scenario(parse_scenario(text), out, quiet=True)
    with Results(out) as r:
        pvd = export_vtk(r, tmp_path / "vtk")
        damage = r.contacts(2)["damage"]
    assert damage.max() > 0.0
    mesh = meshio.read(pvd.parent / "wall" / "contacts_000002.vtu")
    assert np.array_equal(mesh.point_data["damage"], damage)


def test_files_without_the_joint_state_are_read_and_resumed(tmp_path, monkeypatch):
    """A results file written before slip, damage, history and crush existed (made here by writing
    with the older list of contact fields) reads, and resumes bit for bit on the dry laws
    (before: 'damaged beyond reading (object 'slip' doesn't exist)')."""
    import saxum.results as results

    dry = WALL.replace('kind = "cohesive"\n', "").split("k_n =")[0] + WALL.split("g_ii = 2.0\n")[1]
    one_go = tmp_path / "one.h5"
    assert run_scenario(parse_scenario(dry), one_go, quiet=True).status == "finished"
    older = {k: v for k, v in results._CONTACT_FIELDS.items()
             if k not in ("slip", "damage", "history", "crush")}
    monkeypatch.setattr(results, "_CONTACT_FIELDS", older)
    stopped = tmp_path / "stopped.h5"
    original = results.ResultsWriter.log_step

    def log_step(self, report):
        original(self, report)
        if report.step == 1300:
            os.kill(os.getpid(), signal.SIGINT)

    monkeypatch.setattr(results.ResultsWriter, "log_step", log_step)
    assert run_scenario(parse_scenario(dry), stopped, quiet=True).status == "interrupted"
    monkeypatch.undo()
    with results.Results(stopped) as r:
        assert r.frame_count == 27 and not r.damage  # t = 0 .. 0.26 s
        assert "damage" not in r.contacts(5) and "crush" not in r.contacts(5)
        assert "area" in r.contacts(5)
    assert resume_run(stopped, quiet=True).status == "finished"
    same_results(stopped, one_go)


@pytest.mark.parametrize("older", [False, True])
def test_bonds_lost_columns_are_written_and_older_files_read(tmp_path, monkeypatch, older):
    """One step of a bonded pair written with the step log's columns, or as saxum wrote it
    before bonds_lost and damaged (every row intact, no cohesive line in saxum info)."""
    from saxum import results
    from saxum.cli import info_text

    b = sx.ModelBuilder(gravity=(0.0, -9.81))
    b.add_block([(-1, -0.2), (1, -0.2), (1, 0), (-1, 0)], kind=sx.BodyKind.FIXED, group="ground")
    b.add_block([(0, 0), (0.4, 0), (0.4, 0.2), (0, 0.2)], density=2000.0)
    b.set_law("block", "ground", sx.ContactLaw(friction=0.6, **COHESIVE))
    b.set_law("block", "block", sx.ContactLaw(friction=0.6))
    sim = sx.Simulation(b.finalize(), dt=1e-4)
    state = sim.initial_state()
    report = sim.step(state)
    assert (report.bonds_lost, report.damaged) == (0, 0)  # its weight does not crack it
    if older:
        fields = [k for k in results._STEP_FIELDS if k not in ("bonds_lost", "damaged")]
        monkeypatch.setattr(results, "_STEP_FIELDS", fields)
        monkeypatch.setitem(results._ROWS, "steps", (tuple(fields), ()))
    with results.ResultsWriter(tmp_path / "r.h5", sim.model, dt=1e-4,
                               theta=sim.integrator.theta) as w:
        w.log_step(report)
        w.write_frame(state)
    monkeypatch.undo()
    with results.Results(tmp_path / "r.h5") as r:
        assert not r.damage and r.steps["step"].tolist() == [1]
        assert ("bonds_lost" in r.steps) != older
        line = "cohesive joints: no bond cracked; 0 point(s) partly damaged at the end"
        assert (line in info_text(r)) != older
