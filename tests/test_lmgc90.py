"""saxum.lmgc90: reading LMGC90 DATBOX folders, writing them, the round trip, bad input.

The DATBOX folders under tests/data/lmgc90 were written for these tests in LMGC90's layout
(its fixed columns and Fortran reals): `wall2d`, five bricks on a JONCx ground and a driven
ground block, with a partly driven brick, a brick 1 um into the one below (DOF.INI), a
colour without see-tables and a Vloc_Rloc.INI; `block3d`, a POLYR block turned a quarter
turn about z (DOF.INI's frame) 2 um into a PLANx ground; `column2d`, five DISKx grains (radius
0.05 m, a leaning column of four and one beside it) on a fixed JONCx ground; `arch2d`,
LMGC90's arch example with its IQS_CLB_g0 joints (tests/validation/test_lmgc90_examples.py).
"""

import shutil
from pathlib import Path

import numpy as np
import pytest

import saxum as sx
from saxum import NO_CONTACT, BodyKind, ContactLaw, DetectionSettings, LawKind, Simulation
from saxum.cli import main
from saxum.errors import InputError, OverlapError
from saxum.lmgc90 import OVERLAP_TOLERANCE, export_lmgc90, import_lmgc90
from saxum.lmgc90.vlocrloc import read_vloc_rloc
from saxum.scenario import load_scenario, parse_scenario

DATA = Path(__file__).parent / "data" / "lmgc90"


def test_wall2d_bodies_drives_and_laws():
    imported = import_lmgc90(DATA / "wall2d")
    model = imported.model()
    kinds = dict(zip(model.body_name, model.body_kind.tolist(), strict=True))
    assert kinds["RBDY2 1"] == BodyKind.FIXED  # every dof imposed at 0
    assert kinds["RBDY2 2"] == BodyKind.DRIVEN
    assert kinds["RBDY2 6"] == BodyKind.FREE  # one dof of three imposed: left out, listed
    driven = model.motions[model.body_motion[model.body("RBDY2 2")]]
    np.testing.assert_allclose(driven(0.3), (0.0, -0.1, 0.0), atol=1e-15)  # CT exact
    # brick 7: node (0.8, 0.15), DOF.INI X(2) = -1e-6
    lo = model.vertices(model.body("RBDY2 7")).min(axis=0)
    np.testing.assert_allclose(lo, (0.6, 0.1 - 1e-6), atol=1e-12)  # 7-digit file values
    assert model.body_density[model.body("RBDY2 3")] == pytest.approx(2000.0, rel=1e-15)
    laws = imported.laws
    assert laws[("BLEUx", "VERTx")] == ContactLaw(friction=0.5, kind=LawKind.SIGNORINI_COULOMB,
                                                  alert=0.01)
    assert laws[("BLEUx", "GRNDx")].kind == LawKind.GAP_SIGNORINI_COULOMB
    rst = laws[("BLEUx", "REDxx")]
    assert rst.kind == LawKind.RESTITUTION_COULOMB
    assert (rst.restitution, rst.friction, rst.alert) == pytest.approx((0.2, 0.6, 0.005),
                                                                       rel=1e-15)
    # pairs without a see-table pass through each other
    assert laws[("JAUNx", "REDxx")] is NO_CONTACT and ("REDxx", "REDxx") in imported.no_contact
    listed = "\n".join(map(str, imported.untranslated))
    assert "DRV_DOF.DAT line 26: RBDY2 6: only dofs [1] of 3" in listed
    assert "TACT_BEHAV.DAT line 5: law 'rst01': tangential restitution" in listed
    assert model.body_shape[model.body("RBDY2 1")] == sx.Shape.CAPSULE  # the JONCx, exact
    settings = DetectionSettings(initial_overlap=OVERLAP_TOLERANCE)  # brick 7, 1 um in
    state = Simulation(model, dt=1e-3, detection=settings).initial_state()
    imported.set_initial_velocities(model, state)
    np.testing.assert_allclose(state.body_v[model.body("RBDY2 7")], (0.0, -1e-3, 0.0),
                               atol=1e-18)
    np.testing.assert_allclose(state.body_v[model.body("RBDY2 2")], (0.0, -0.1, 0.0),
                               atol=1e-15)  # the driven ground keeps its drive's


def test_micrometre_interpenetration_accepted_real_overlap_refused():
    imported = import_lmgc90(DATA / "wall2d")
    model = imported.model()
    # brick 7 was put 1e-6 m into brick 4 below it; 1e-12: 7-digit file values
    depth, a, b = imported.deepest_overlap(model)
    assert depth == pytest.approx(1e-6, abs=1e-12) and {a, b} == {"RBDY2 7", "RBDY2 4"}
    assert imported.check_overlaps(model) == pytest.approx(1e-6, abs=1e-12)
    with pytest.raises(OverlapError, match="overlap by 1e-06 m"):
        imported.check_overlaps(model, tolerance=1e-7)


def test_block3d_frame_and_plane():
    imported = import_lmgc90(DATA / "block3d")
    model = imported.model()
    b = model.body("RBDY3 2")
    # local box 0.4 x 0.2 x 0.1 turned a quarter turn about z: 0.2 along x, 0.4 along y
    pts = model.vertices(b)
    np.testing.assert_allclose(pts.min(axis=0), (-0.1, -0.2, -2e-6), atol=1e-12)
    np.testing.assert_allclose(pts.max(axis=0), (0.1, 0.2, 0.1 - 2e-6), atol=1e-12)
    assert model.body_kind[model.body("RBDY3 1")] == BodyKind.FIXED
    np.testing.assert_allclose(model.vertices(model.body("RBDY3 1")).max(axis=0),
                               (1.0, 1.0, 0.0), atol=1e-12)
    # V(4..6) in LMGC90's body axes (g = z): 0.5 rad/s about z; saxum's body frame of the
    # box is the world's (principal axes along x, y, z)
    settings = DetectionSettings(initial_overlap=OVERLAP_TOLERANCE)  # the 2 um into the plane
    state = Simulation(model, dt=1e-3, detection=settings).initial_state()
    imported.set_initial_velocities(model, state)
    np.testing.assert_allclose(np.abs(state.body_v[b, 3:]), (0.0, 0.0, 0.5), atol=1e-12)
    assert imported.deepest_overlap(model)[0] == pytest.approx(2e-6, abs=1e-12)


def _settled_wall():
    text = """
[structure]
type = "wall"
courses = 3
bricks = 3
ground_splits = [0.25]
[[laws]]
groups = ["brick", "ground"]
friction = 0.6
kind = "signorini_coulomb"
alert = 0.004
[[laws]]
groups = ["brick", "brick"]
kind = "restitution_coulomb"
restitution = 0.3
friction = 0.5
[[laws]]
groups = ["ground", "ground"]
kind = "none"
[[loads.settlements]]
block = "ground 2"
magnitude = 0.02
time = 0.2
[output]
duration = 0.2
"""
    return parse_scenario(text).build_simulation()


def _same_models(a, b, tol):
    """Same blocks (names, groups, kinds, densities, world vertices within tol of the model's
    size) and the same law for every pair of groups."""
    assert a.body_name == b.body_name
    assert [a.group_names[g] for g in a.body_group] == [b.group_names[g] for g in b.body_group]
    np.testing.assert_array_equal(a.body_kind, b.body_kind)
    np.testing.assert_allclose(b.body_density, a.body_density, rtol=1e-15)
    np.testing.assert_allclose(b.body_round_radius, a.body_round_radius, rtol=1e-15)
    scale = float(np.abs(np.concatenate([a.vertices(k) for k in range(a.body_count)])).max())
    for k in range(a.body_count):
        va, vb = a.vertices(k), b.vertices(k)
        # the same points, in whatever order each model keeps them
        apart = np.linalg.norm(va[:, None, :] - vb[None, :, :], axis=2)
        assert len(va) == len(vb) and apart.min(axis=1).max() <= tol * scale
    for i, gi in enumerate(a.group_names):
        for j, gj in enumerate(a.group_names):
            la, lb = a.group_law[i, j], b.group_law[b.group_names.index(gi),
                                                    b.group_names.index(gj)]
            assert (la < 0) == (lb < 0)
            if la >= 0:
                x, y = a.laws[la], b.laws[lb]
                assert x.kind == y.kind and y.alert is not None  # LMGC90: one per see-table
                assert x.initial_gap == y.initial_gap  # a _g0 law
                if x.alert is not None:
                    assert y.alert == pytest.approx(x.alert, rel=1e-15)
                assert (y.friction, y.restitution) == pytest.approx(
                    (x.friction, x.restitution), rel=1e-15)


def test_round_trip_2d_full_precision(tmp_path):
    sim = _settled_wall()
    model = sim.model
    export_lmgc90(model, tmp_path / "DATBOX", precision="full", alert=sim.detector.alert)
    back = import_lmgc90(tmp_path / "DATBOX")
    again = back.model()
    # 17 significant digits: the round trip is exact up to the sum centre + local vertex
    _same_models(model, again, 1e-12)
    drive = again.motions[again.body_motion[again.body("ground 2")]]
    original = model.motions[model.body_motion[model.body("ground 2")]]
    np.testing.assert_allclose(drive(0.0), original(0.0), rtol=1e-15)
    alerts = sorted({law.alert for law in again.laws})
    assert alerts == pytest.approx(sorted((0.004, sim.detector.alert)), rel=1e-15)


def test_round_trip_3d_and_lmgc90_columns(tmp_path):
    scenario = parse_scenario("""
[structure]
type = "semicircular_arch_3d"
radius = 1.0
thickness = 0.15
voussoirs = 5
depth = 0.3
[[laws]]
groups = ["*", "*"]
friction = 0.7
[output]
duration = 0.1
""")
    model = scenario.build_model()
    export_lmgc90(model, tmp_path / "full", precision="full", alert=0.003)
    _same_models(model, import_lmgc90(tmp_path / "full").model(), 1e-12)
    # LMGC90's fixed columns: 7 significant digits, each value within half a unit of its
    # last digit (5e-8 relative), centre and local vertex added: 1e-7 of the model's size
    export_lmgc90(model, tmp_path / "cols", alert=0.003)
    text = (tmp_path / "cols" / "BODIES.DAT").read_text()
    assert " NO6xx      1                coo1=" in text
    _same_models(model, import_lmgc90(tmp_path / "cols").model(), 1e-7)


def test_g0_laws_round_trip(tmp_path):
    """ContactLaw.initial_gap is written as LMGC90's _g0 law and read back as it, through
    the scenario too, and is not listed as untranslated."""
    b = sx.ModelBuilder()
    b.add_block([(-1, -0.1), (1, -0.1), (1, 0), (-1, 0)], kind=BodyKind.FIXED, group="ground")
    b.add_block([(0, 0.002), (0.2, 0.002), (0.2, 0.4), (0, 0.4)], density=2000.0, group="stone")
    b.add_block([(0, 0.41), (0.2, 0.41), (0.2, 0.6), (0, 0.6)], density=2000.0, group="stone")
    b.set_law("stone", "ground", ContactLaw(friction=0.6, kind=LawKind.SIGNORINI_COULOMB,
                                            initial_gap=True, alert=0.02))
    b.set_law("stone", "stone", ContactLaw(friction=0.5, initial_gap=True, alert=0.02))
    model = b.finalize()
    export_lmgc90(model, tmp_path / "DATBOX", precision="full")
    tact = (tmp_path / "DATBOX" / "TACT_BEHAV.DAT").read_text()
    assert "IQS_CLB_g0" in tact and "GAP_SGR_CLB_g0" in tact
    back = import_lmgc90(tmp_path / "DATBOX")
    assert not back.untranslated
    _same_models(model, back.model(), 1e-12)
    back.write_scenario(tmp_path / "model.toml")
    _same_models(model, load_scenario(tmp_path / "model.toml").build_model(), 1e-12)
    # a state's Vloc_Rloc.INI: each contact of a _g0 law ends with LMGC90's internal
    # variables, a '#' line naming them and their values (g_ref = g0 last, 7 digits)
    sim = Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 0.01)
    export_lmgc90(model, tmp_path / "STATE", state=state, dt=1e-3)
    lines = (tmp_path / "STATE" / "Vloc_Rloc.INI").read_text().splitlines()
    names = [k for k, line in enumerate(lines) if line.startswith("#")]
    c = state.contacts
    assert len(names) == c.count and c.count > 0
    iqs = [lines[k] for k in names].count("#g_ref         ")
    assert iqs == int(np.count_nonzero(c.law[:c.count] == model.group_law[0, 1]))
    values = [float(lines[k + 1].split()[-1].replace("D", "E")) for k in names]
    np.testing.assert_allclose(values, c.initial_gap[:c.count], rtol=5e-8, atol=0.0)
    assert max(values) > 0.005  # the 1 cm gap between the stones
    assert len(read_vloc_rloc(tmp_path / "STATE" / "Vloc_Rloc.INI")) == c.count


def test_scenario_from_import_runs_like_the_python_model(tmp_path):
    imported = import_lmgc90(DATA / "wall2d")
    extra = imported.write_scenario(tmp_path / "model.toml", duration=0.05)
    text = (tmp_path / "model.toml").read_text()
    assert "#   TACT_BEHAV.DAT line 5: law 'rst01'" in text
    assert any("RBDY2 7: initial velocity" in str(item) for item in extra)
    assert 'groups = ["JAUNx", "REDxx"]\nkind = "none"' in text
    scenario = load_scenario(tmp_path / "model.toml")
    assert scenario.detection.initial_overlap == pytest.approx(1e-5, rel=1e-15)
    sim = scenario.build_simulation()
    sim.initial_state()  # the 1 um interpenetration is accepted (detection.initial_overlap)
    tight = load_scenario(tmp_path / "model.toml", ["detection.initial_overlap=5e-7"])
    with pytest.raises(OverlapError, match="overlap by 1e-06 m"):
        tight.build_simulation().initial_state()
    _same_models(imported.model(), sim.model, 1e-15)
    ground = sim.model.body("RBDY2 2")
    np.testing.assert_allclose(sim.model.motions[sim.model.body_motion[ground]](0.01),
                               (0.0, -0.1, 0.0), rtol=1e-14, atol=1e-18)


def test_time_varying_drive(tmp_path):
    # ground block 2: vy = [-0.1 + 0.05 cos(2 t + 0.5)] [1 + 0.5 t]
    folder, line = _broken(tmp_path, "DRV_DOF.DAT",
                           " vlocy      2 -1.0000000D-01   0.0000000D+00   0.0000000D+00   "
                           "0.0000000D+00   1.0000000D+00   0.0000000D+00",
                           " vlocy      2 -1.0000000D-01   5.0000000D-02   2.0000000D+00   "
                           "5.0000000D-01   1.0000000D+00   5.0000000D-01")
    imported = import_lmgc90(folder)
    model = imported.model()
    motion = model.motions[model.body_motion[model.body("RBDY2 2")]]
    t = 0.7
    expected = (-0.1 + 0.05 * np.cos(2.0 * t + 0.5)) * (1.0 + 0.5 * t)
    assert motion(t)[1] == pytest.approx(expected, rel=1e-14)  # the formula, exactly
    extra = imported.write_scenario(tmp_path / "m.toml")
    assert any(f"DRV_DOF.DAT line {line}" in str(e) and "time-varying" in str(e)
               for e in extra)


def _broken(tmp_path, file, old, new):
    folder = tmp_path / "DATBOX"
    shutil.copytree(DATA / "wall2d", folder)
    text = (folder / file).read_text()
    assert old in text
    (folder / file).write_text(text.replace(old, new, 1))
    line = text[:text.index(old)].count("\n") + 1
    return folder, line


@pytest.mark.parametrize("file, old, new, message", [
    ("BODIES.DAT", " RBDY2      8", " MAILx      8", "body type MAILx"),
    ("BODIES.DAT", " POLYG      1  color  JAUNx", " xKSID      1  color  JAUNx",
     "contactor xKSID of RBDY2 8 is not translated"),
    ("TACT_BEHAV.DAT", " gap01  GAP_SGR_CLB", " gap01  IQS_MOHR_DS_CLB",
     "law 'gap01' of type IQS_MOHR_DS_CLB has no saxum equivalent"),
    ("TACT_BEHAV.DAT", " RBDY2  POLYG  REDxx  rst01", " RBDY2  POLYG  ROSEx  rst01",
     "names colour 'ROSEx', which no body has"),
    ("DOF.INI", " RBDY2      7", " RBDY2     99", "DOF.INI gives RBDY2 99, which BODIES.DAT"),
])
def test_bad_input_names_file_and_line(tmp_path, capsys, file, old, new, message):
    folder, line = _broken(tmp_path, file, old, new)
    # the line named is the one changed (or, for a contactor's law, the law's)
    with pytest.raises(InputError, match=f"{file} line {line}: .*{message}"):
        import_lmgc90(folder)
    assert main(["import-lmgc90", str(folder), "-o", str(tmp_path / "m.toml")]) == 2
    assert message.split("'")[0] in capsys.readouterr().err
    assert not (tmp_path / "m.toml").exists()


def test_cli_round_trip_and_real_overlap(tmp_path, capsys):
    scenario = tmp_path / "arch.toml"
    scenario.write_text("""
[structure]
type = "semicircular_arch"
radius = 1.0
thickness = 0.15
voussoirs = 5
[[laws]]
groups = ["*", "*"]
friction = 0.6
[output]
duration = 0.1
""")
    assert main(["export-lmgc90", str(scenario), "-o", str(tmp_path / "DATBOX")]) == 0
    assert main(["import-lmgc90", str(tmp_path / "DATBOX"), "-o", str(tmp_path / "m.toml")]) == 0
    out = capsys.readouterr().out
    assert "6 blocks (5 free, 1 fixed, 0 driven)" in out and "deepest interpenetration" in out
    # an existing scenario is not replaced without --overwrite
    assert main(["import-lmgc90", str(tmp_path / "DATBOX"), "-o", str(tmp_path / "m.toml")]) == 2
    assert "give --overwrite" in capsys.readouterr().err
    assert main(["import-lmgc90", str(tmp_path / "DATBOX"), "-o", str(tmp_path / "m.toml"),
                 "--overwrite"]) == 0
    # a voussoir pushed 1 mm into its neighbour: a real overlap, refused
    dof = tmp_path / "DATBOX" / "DOF.INI"
    text = dof.read_text()
    start = text.index(" RBDY2      3")
    dof.write_text(text[:start] + text[start:].replace("X(1)= 0.0000000D+00",
                                                       "X(1)= 5.0000000D-02", 1))
    assert main(["import-lmgc90", str(tmp_path / "DATBOX"), "-o", str(tmp_path / "n.toml")]) == 2
    assert "a real overlap" in capsys.readouterr().err


def _column_in_python():
    """column2d (tests/data/lmgc90) built with ModelBuilder from the numbers in its files."""
    b = sx.ModelBuilder()
    # JONCx ax1 = 0.5, ax2 = 0.05 at node (0, -0.05): a capsule, segment 1.0, radius 0.05
    b.add_capsule((0.0, -0.05), 1.0, 0.05, group="GRNDx", kind=BodyKind.FIXED, name="RBDY2 1")
    for k, (x, y) in enumerate([(0.0, 0.051), (0.004, 0.153), (-0.003, 0.255),
                                (0.006, 0.357), (0.11, 0.05)]):
        b.add_disc((x, y), 0.05, density=2000.0, group="GRAIx", name=f"RBDY2 {k + 2}")
    gap = LawKind.GAP_SIGNORINI_COULOMB  # GAP_SGR_CLB
    b.set_law("GRAIx", "GRAIx", ContactLaw(friction=0.4, kind=gap, alert=0.002))
    b.set_law("GRAIx", "GRNDx", ContactLaw(friction=0.6, kind=gap, alert=0.002))
    return b.finalize()


def _settle(model, steps=150):
    sim = Simulation(model, dt=1e-3)
    state = sim.initial_state()
    for _ in range(steps):
        sim.step(state)
    return sim, state


def test_discs_imported_run_like_the_python_model():
    imported = import_lmgc90(DATA / "column2d")
    model = imported.model()
    assert model.body_round_radius.tolist() == [0.05] * 6  # byrd=, JONCx ax2= 5.0000000D-02
    assert not any("DISKx" in str(item) for item in imported.untranslated)
    sim_a, a = _settle(model)
    sim_b, b = _settle(_column_in_python())
    # the same model by two routes: bit-identical positions (one machine, one test)
    assert np.array_equal(a.body_q, b.body_q) and np.array_equal(a.body_v, b.body_v)
    assert a.body_q[1:, 1].max() < 0.357 - 0.01  # the column has moved (fallen)
    # the gap law: no interpenetration beyond the detector's tolerated one
    probe = sim_a.detector.contacts_at(a.body_q)
    assert probe.gap[:probe.count].min() > -sim_a.detector.interpenetration


def test_discs_and_spheres_round_trip(tmp_path):
    imported = import_lmgc90(DATA / "column2d")
    model = imported.model()
    imported.write_scenario(tmp_path / "column.toml")  # discs as "centre" and "radius"
    _same_models(model, load_scenario(tmp_path / "column.toml").build_model(), 1e-15)
    export_lmgc90(model, tmp_path / "disc", precision="full")
    text = (tmp_path / "disc" / "TACT_BEHAV.DAT").read_text()
    assert "RBDY2  DISKx  GRA01  law01  RBDY2  DISKx  GRA01" in text
    assert "RBDY2  DISKx  GRA01  law02  RBDY2  JONCx  GRN02" in text  # the disc: candidate
    _same_models(model, import_lmgc90(tmp_path / "disc").model(), 1e-12)
    b = sx.ModelBuilder(dim=3)
    b.add_plane((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), (1.0, 1.0), name="ground")
    b.add_sphere((0.1, 0.2, 0.3), 0.07, density=2500.0, name="ball")
    b.add_block([(x, y, z) for x in (0.3, 0.5) for y in (0.0, 0.2) for z in (0.0, 0.2)],
                density=2000.0, name="brick")
    b.set_law("block", "block", ContactLaw(friction=0.5, alert=0.003))
    b.set_law("block", "ground", ContactLaw(friction=0.5, alert=0.003))
    model3 = b.finalize()
    export_lmgc90(model3, tmp_path / "sphere", precision="full")
    assert "SPHER      1  color  BLO01  byrd=" in (tmp_path / "sphere" / "BODIES.DAT").read_text()
    back = import_lmgc90(tmp_path / "sphere").model()
    _same_models(model3, back, 1e-12)
    assert back.body_round_radius[back.body("ball")] == pytest.approx(0.07, rel=1e-15)


@pytest.mark.parametrize("old, new, message", [
    ("byrd= 5.0000000D-02", "byrd= 0.0000000D+00", "DISKx of RBDY2 2 has byrd = 0"),
    ("byrd= 5.0000000D-02", "byrd= 5.0000000D-02  coo1= 1.0000000D-02",
     "DISKx of RBDY2 2 has a shift coo1"),
])
def test_bad_disc_named_with_its_line(tmp_path, old, new, message):
    folder = tmp_path / "DATBOX"
    shutil.copytree(DATA / "column2d", folder)
    text = (folder / "BODIES.DAT").read_text()
    (folder / "BODIES.DAT").write_text(text.replace(old, new, 1))
    line = text[:text.index(old)].count("\n") + 1
    with pytest.raises(InputError, match=f"BODIES.DAT line {line}: {message}"):
        import_lmgc90(folder)
