"""LMGC90's Vloc_Rloc impulses as the first step's warm start (saxum.lmgc90.vlocrloc,
saxum.warmstart), and capsules (LMGC90's JONCx) through DATBOX and block files.

tests/data/lmgc90/wall2d/Vloc_Rloc.INI was written for these tests in the columns of LMGC90's
write_out_Vloc_Rloc (mod_PLPLx.f90, mod_PLJCx.f90): a PLPLx contact, a PLJCx contact (whose
candidate is the brick, where saxum's is the capsule) and one at a point where saxum finds
no contact.
"""

import json
import shutil
from pathlib import Path

import numpy as np
import pytest

import saxum as sx
from saxum import NLGS, BodyKind, ContactLaw, DetectionSettings, Simulation
from saxum.cli import main
from saxum.errors import InputError
from saxum.lmgc90 import OVERLAP_TOLERANCE, export_lmgc90, import_lmgc90
from saxum.runner import run_scenario
from saxum.scenario import load_scenario
from saxum.structures.blockfile import blocks_model, write_blocks

DATA = Path(__file__).parent / "data" / "lmgc90"
DT = 1e-3


def _solver():
    # NLGS alone, no rest solution: the sweeps counted are those from the warm start
    return NLGS(tolerance=1e-6, max_iterations=5000, rest_after=0)


def test_vloc_rloc_read_and_matched():
    imported = import_lmgc90(DATA / "wall2d")
    assert [e.module for e in imported.impulses] == ["PLPLx", "PLJCx", "PLPLx"]
    assert [e.status for e in imported.impulses] == ["stick"] * 3
    model = imported.model()
    sim = Simulation(model, dt=DT, solver=_solver(),
                     detection=DetectionSettings(initial_overlap=OVERLAP_TOLERANCE))
    state = sim.initial_state()
    used, notes = imported.warm_start(sim, state)
    assert len(used) == 2
    # the third: no contact of bricks 5 and 2 at (2, 0) (theirs end at x = 1.2), listed
    assert len(notes) == 1 and "Vloc_Rloc.INI line 26" in str(notes[0])  # its body line
    assert "no contact of these blocks within" in str(notes[0])
    c = state.contacts
    names = [(model.body_name[c.candidate[k]], model.body_name[c.antagonist[k]])
             for k in range(c.count)]
    # PLPLx, brick 4 on ground 2 at (0.6, 0): rlt/H 1.5, rln/H 40 [N] in the same roles
    k = next(k for k in range(c.count) if names[k] == ("RBDY2 4", "RBDY2 2")
             and abs(c.point[k, 0] - 0.6) < 1e-9)
    np.testing.assert_allclose(c.impulse[k], (1.5 * DT, 40.0 * DT), rtol=1e-15)
    # PLJCx, brick 3 on the JONCx 1 (n up): saxum's candidate is the capsule, n down; the
    # force on the brick, (-2, 30) N, is minus the capsule's: components -2, 30 again
    k = next(k for k in range(c.count) if names[k] == ("RBDY2 1", "RBDY2 3")
             and abs(c.point[k, 0] - 0.4) < 1e-9)
    # (saxum's normal there is off by ~1e-15 rad, the round-off of the capsule's frame: the
    # normal 30 N leaks ~3e-14 N into the tangent; 1e-12 of the impulse bounds it)
    np.testing.assert_allclose(c.impulse[k], (-2.0 * DT, 30.0 * DT), rtol=0,
                               atol=1e-12 * 30.0 * DT)
    assert np.count_nonzero(c.impulse[:c.count, 1]) == 2  # the others start from zero


def _wall():
    """An LMGC90-style wall: 3 courses of 3 bricks 0.2 x 0.1 m (offset by half a brick) on
    a fixed JONCx-like capsule ground, Signorini-Coulomb (IQS_CLB) mu = 0.5."""
    b = sx.ModelBuilder()
    b.add_capsule((0.35, -0.05), 1.0, 0.05, kind=BodyKind.FIXED, group="ground", name="ground")
    for k in range(3):
        for i in range(3):
            x = 0.1 * (k % 2) + 0.2 * i
            b.add_block([(x, 0.1 * k), (x + 0.2, 0.1 * k), (x + 0.2, 0.1 * k + 0.1),
                         (x, 0.1 * k + 0.1)], density=2000.0, group="brick",
                        name=f"brick {k}.{i}")
    law = ContactLaw(friction=0.5, alert=0.002)
    b.set_law("brick", "brick", law)
    b.set_law("brick", "ground", law)
    model = b.finalize()
    sim = Simulation(model, dt=DT, solver=_solver())
    state = sim.initial_state()
    for _ in range(30):
        sim.step(state)
    return sim, state


def test_round_trip_and_fewer_sweeps(tmp_path):
    sim, state = _wall()
    model = sim.model
    export_lmgc90(model, tmp_path / "DATBOX", state=state, dt=DT)
    text = (tmp_path / "DATBOX" / "Vloc_Rloc.INI").read_text()
    assert "$icdan  PLJCx" in text and " RBDY2      2  POLYG      1  CDVER" in text
    imported = import_lmgc90(tmp_path / "DATBOX")
    back = imported.model()
    assert back.body_shape[back.body("ground")] == sx.Shape.CAPSULE
    warm_sim = Simulation(back, dt=DT, solver=_solver(),
                          detection=DetectionSettings(initial_overlap=OVERLAP_TOLERANCE))
    warm = warm_sim.initial_state()
    used, notes = imported.warm_start(warm_sim, warm)
    loaded = int(np.count_nonzero(np.abs(state.contacts.impulse[:state.contacts.count]).sum(1)))
    assert not notes and len(used) == loaded  # open contacts (R = 0) need no warm start
    # the same impulses within the file's 7 digits: each force rounded to 5e-8 relative, the
    # positions (and so the frames) to 1e-7 of the model's size: 1e-6 of the largest impulse
    a, b = state.contacts, warm.contacts
    scale = np.abs(a.impulse[:a.count]).max()
    for k in range(a.count):
        same = [j for j in range(b.count) if (b.candidate[j], b.antagonist[j])
                == (a.candidate[k], a.antagonist[k])]
        j = same[int(np.argmin(np.linalg.norm(b.point[same] - a.point[k], axis=1)))]
        np.testing.assert_allclose(b.impulse[j], a.impulse[k], rtol=0, atol=1e-6 * scale)
    # the first step from these impulses against the same step from zero
    cold_sim = Simulation(back, dt=DT, solver=_solver(),
                          detection=DetectionSettings(initial_overlap=OVERLAP_TOLERANCE))
    cold = cold_sim.initial_state()
    warm_report, cold_report = warm_sim.step(warm), cold_sim.step(cold)
    assert warm_report.converged and cold_report.converged
    assert warm_report.iterations * 3 < cold_report.iterations


def test_cli_writes_warm_start_and_run_uses_it(tmp_path, capsys):
    sim, state = _wall()
    export_lmgc90(sim.model, tmp_path / "DATBOX", state=state, dt=DT, precision="full")
    assert main(["import-lmgc90", str(tmp_path / "DATBOX"), "-o", str(tmp_path / "w.toml"),
                 "--dt", str(DT), "--duration", str(2 * DT)]) == 0
    out = capsys.readouterr().out
    c = state.contacts
    count = c.count
    loaded = int(np.count_nonzero(np.abs(c.impulse[:count]).sum(1)))
    assert (f"{loaded} of {count} contacts' impulses are the first step's warm start "
            f"(solver.warm_start); {count - loaded} are 0") in out
    scenario = load_scenario(tmp_path / "w.toml")
    assert Path(scenario.solver.warm_start) == tmp_path / "w.impulses.json"
    forces = sx.read_warm_start(scenario.solver.warm_start)
    assert len(forces) == loaded
    run_scenario(scenario, tmp_path / "w.h5")
    # a force on blocks the model does not have: refused, named
    data = json.loads((tmp_path / "w.impulses.json").read_text())
    data["contacts"][0]["candidate"] = "nobody"
    (tmp_path / "w.impulses.json").write_text(json.dumps(data))
    with pytest.raises(InputError, match="(?s)match no contact.*no block 'nobody'"):
        run_scenario(load_scenario(tmp_path / "w.toml"), tmp_path / "x.h5")


DKDK = """
! Vloc_Rloc
$steps      500              time= 0.2000000D+00
$icdan  DKDKx      439
 cdbdy  numbr  cdtac  numbr  behav  anbdy  numbr  antac  numbr  sttus   iadj
 RBDY2      1  DISKx      1  iqsc0  RBDY2     11  DISKx      1  slifw     11
                             rlt/H-0.2500000D+01  rln/H 0.5000000D+01  rls/H 0.0000000D+00
                             vlt = 0.6650118D-04  vln = 0.0000000D+00  vls = 0.0000000D+00
                             gapTT-0.8011855D-08
                             n(1)= 0.6000000D+00  n(2)=-0.8000000D+00  n(3)= 0.0000000D+00
                             coo1= 0.4673217D-01  coo2=-0.2811716D-02  coo3= 0.0000000D+00

$icdan  DKDKx      440
 cdbdy  numbr  cdtac  numbr  behav  anbdy  numbr  antac  numbr  sttus   iadj
 RBDY2      2  DISKx      1  iqsc0  RBDY2      4  DISKx      1  noctc      4
                             rlt/H 0.0000000D+00  rln/H 0.0000000D+00  rls/H 0.0000000D+00
                             gapTT 0.1596192D-03
                             n(1)=-0.9942585D+00  n(2)= 0.1070046D+00  n(3)= 0.0000000D+00
                             coo1= 0.2687885D-01  coo2=-0.1750811D-02  coo3= 0.0000000D+00
"""


def test_disc_contacts_in_lmgc90_columns(tmp_path):
    # DKDKx's layout (mod_DKDKx.f90): no vertex or segment on the body line, a negative
    # value against its label (gapTT-0.80D-08), an open contact (noctc) with zero impulses
    from saxum.lmgc90.vlocrloc import read_vloc_rloc

    (tmp_path / "Vloc_Rloc.INI").write_text(DKDK)
    first, second = read_vloc_rloc(tmp_path / "Vloc_Rloc.INI")
    assert first.candidate == ("RBDY2", 1, "DISKx") and first.antagonist == ("RBDY2", 11, "DISKx")
    assert first.status == "slifw" and first.values["gapTT"] == pytest.approx(-0.8011855e-8,
                                                                               rel=1e-15)
    # t = (n2, -n1) = (-0.8, -0.6): F = -2.5 t + 5 n = (5, -2.5)
    np.testing.assert_allclose(first.force(2), (5.0, -2.5), rtol=0, atol=1e-14)
    assert not first.zero and second.zero and second.status == "noctc"


def test_bad_vloc_rloc_line_named(tmp_path):
    folder = tmp_path / "DATBOX"
    shutil.copytree(DATA / "wall2d", folder)
    path = folder / "Vloc_Rloc.INI"
    text = path.read_text()
    path.write_text(text.replace(" RBDY2      4  POLYG", " RBDY2      x  POLYG", 1))
    line = text[:text.index(" RBDY2      4  POLYG")].count("\n") + 1
    with pytest.raises(InputError, match=f"Vloc_Rloc.INI line {line}: cannot read the contact"):
        import_lmgc90(folder)


def test_capsule_in_block_file_and_datbox(tmp_path):
    b = sx.ModelBuilder()
    b.add_capsule((0.3, -0.05), 0.6, 0.05, angle=0.2, kind=BodyKind.FIXED, group="ground",
                  name="ground")
    b.add_block([(0, 0.1), (0.2, 0.1), (0.2, 0.2), (0, 0.2)], density=2000.0, name="brick")
    b.set_law("block", "ground", ContactLaw(friction=0.5, alert=0.002))
    b.set_law("block", "block", ContactLaw(friction=0.5, alert=0.002))
    model = b.finalize()
    write_blocks(tmp_path / "blocks.json", model)
    row = json.loads((tmp_path / "blocks.json").read_text())["blocks"][0]
    assert row["length"] == pytest.approx(0.6, rel=1e-14) and row["angle"] == pytest.approx(
        0.2, rel=1e-14)  # read back from the bounding rectangle: round-off only
    again = blocks_model(tmp_path / "blocks.json")
    np.testing.assert_allclose(again.vertices(0), model.vertices(0), rtol=0, atol=1e-15)
    assert again.body_shape[0] == sx.Shape.CAPSULE
    export_lmgc90(model, tmp_path / "DATBOX", precision="full")
    assert "JONCx      1  color  GRO" in (tmp_path / "DATBOX" / "BODIES.DAT").read_text()
    back = import_lmgc90(tmp_path / "DATBOX").model()
    assert back.body_round_radius[back.body("ground")] == pytest.approx(0.05, rel=1e-15)
    np.testing.assert_allclose(back.vertices(back.body("ground")), model.vertices(0),
                               rtol=0, atol=1e-14)
    with pytest.raises(InputError, match=r"blocks\[0\].*a capsule needs a length > 0"):
        (tmp_path / "bad.json").write_text(json.dumps(
            {"blocks": [{"centre": [0, 0], "radius": 0.1, "length": 0.0}]}))
        blocks_model(tmp_path / "bad.json")


def test_round_trip_3d_same_forces(tmp_path):
    b = sx.ModelBuilder(dim=3)
    b.add_block([(x, y, z) for x in (-1, 1) for y in (-1, 1) for z in (-0.1, 0)],
                kind=BodyKind.FIXED, group="ground", name="ground")
    for k in range(3):  # a stack of three bricks, each offset by 0.1 m
        x0 = 0.1 * (k % 2)
        b.add_block([(x, y, z) for x in (x0, x0 + 0.3) for y in (0, 0.2)
                     for z in (0.1 * k, 0.1 * k + 0.1)], density=2000.0, group="brick",
                    name=f"brick {k}")
    b.set_law("brick", "brick", ContactLaw(friction=0.5, alert=0.002))
    b.set_law("brick", "ground", ContactLaw(friction=0.5, alert=0.002))
    sim = Simulation(b.finalize(), dt=DT, solver=_solver())
    state = sim.initial_state()
    for _ in range(20):
        sim.step(state)
    export_lmgc90(sim.model, tmp_path / "DATBOX", state=state, dt=DT, precision="full")
    assert "$icdan  PRPRx" in (tmp_path / "DATBOX" / "Vloc_Rloc.INI").read_text()
    imported = import_lmgc90(tmp_path / "DATBOX")
    warm_sim = Simulation(imported.model(), dt=DT, solver=_solver(),
                          detection=DetectionSettings(initial_overlap=OVERLAP_TOLERANCE))
    warm = warm_sim.initial_state()
    used, notes = imported.warm_start(warm_sim, warm)
    assert not notes and len(used) == np.count_nonzero(
        np.abs(state.contacts.impulse[:state.contacts.count]).sum(1))
    # the tangents of a face contact are the detector's choice (the re-imported bodies'
    # frames differ), so compare the world forces; 17 digits: 1e-12 of the largest
    a, c = state.contacts, warm.contacts
    world = [a.frame[k].T @ a.impulse[k] for k in range(a.count)]
    scale = np.abs(world).max()
    for k in range(a.count):
        same = [j for j in range(c.count) if (c.candidate[j], c.antagonist[j])
                == (a.candidate[k], a.antagonist[k])]
        j = same[int(np.argmin(np.linalg.norm(c.point[same] - a.point[k], axis=1)))]
        np.testing.assert_allclose(c.frame[j].T @ c.impulse[j], world[k], rtol=0,
                                   atol=1e-12 * scale)
