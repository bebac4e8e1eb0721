"""What the outputs say about mortar joints (COHESIVE law): the mechanism report names the
cracked and damaged joints, `saxum plot` draws each bond point coloured by its state with a
legend, and the ParaView export carries the damage of each contact."""

import meshio
import numpy as np
import pytest
from matplotlib.figure import Figure

import saxum as sx
from saxum.laws import LawKind
from saxum.mechanism import bond_states, frame_mechanism, mechanism
from saxum.plot import plot_frame
from saxum.results import Results, ResultsWriter
from saxum.vtk import export_vtk

DT = 2e-4


def _column(cohesive: bool = True) -> sx.Model:
    """Two 0.5 m blocks bonded on a fixed base, the upper one pushed sideways hard enough to
    crack the base joint (f_t b^2 / 3 + N b / 2 about 8.7 kN m/m) within a few milliseconds."""
    law = (sx.ContactLaw(friction=0.6, kind=LawKind.COHESIVE, k_n=1e10, k_t=4e9, f_t=1e5,
                         cohesion=5e5, g_i=10.0, g_ii=100.0, points=3) if cohesive
           else sx.ContactLaw(friction=0.6))
    builder = sx.ModelBuilder()
    builder.add_block([(-1, -0.5), (1, -0.5), (1, 0), (-1, 0)], kind=sx.BodyKind.FIXED,
                      group="base", name="base")
    for k in range(2):
        builder.add_block([(0, 0.5 * k), (0.5, 0.5 * k), (0.5, 0.5 * (k + 1)),
                           (0, 0.5 * (k + 1))], density=2000.0, name=f"block {k + 1}")
    builder.set_law("block", "block", law)
    builder.set_law("block", "base", law)
    builder.add_force([2], lambda t: (4e6 * t, 0.0, 0.0))  # 12 kN/m (1.5 kN m/m) per ms
    return builder.finalize()


@pytest.fixture(scope="module")
def cracked(tmp_path_factory):
    """A results file of the column until its base joint has cracked through one point, and
    the simulation and state at the end."""
    model = _column()
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state()
    path = tmp_path_factory.mktemp("bonds") / "column.h5"
    with ResultsWriter(path, model, dt=DT, theta=sim.integrator.theta) as w:
        w.write_frame(state)
        while not (state.contacts.damage[: state.contacts.count] >= 1.0).any():
            sim.step(state)
            assert state.time < 0.05, "the base joint did not crack"
            if state.step % 5 == 0:
                w.write_frame(state)
        w.write_frame(state)
    return path, sim, state


def test_bond_states_label_the_bonds_of_cohesive_contacts_only():
    law_kind = np.array([LawKind.GAP_SIGNORINI_COULOMB, LawKind.COHESIVE], dtype=np.int8)
    # the last contact: cohesive but made after the start, so never bonded (saxum.contacts)
    labels = bond_states(np.array([0, 1, 1, 1, 1]), np.array([1.0, 0.0, 0.3, 1.0, 1.0]),
                         np.array([0.0, 0.5, 1.2, 7.0, 0.0]), law_kind)
    assert labels.tolist() == ["", "intact", "damaged", "cracked", ""]


def test_mechanism_report_names_the_cracked_joint(cracked):
    path, sim, state = cracked
    with Results(path) as r:
        from_file = frame_mechanism(r, -1)
    for mech in (mechanism(sim.model, state, DT), from_file):
        bonds = {j.bodies: j.bond for j in mech.joints}
        assert bonds[("base", "block 1")] == "cracked"
        assert bonds[("block 1", "block 2")] in ("intact", "damaged")
        assert "cracked joints (bond broken): base | block 1" in mech.text()


def test_dry_joints_have_no_bond():
    model = _column(cohesive=False)
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state()
    sim.step(state)
    mech = mechanism(model, state, DT)
    assert mech.joints and all(j.bond is None for j in mech.joints)
    assert "bond" not in mech.text()


def test_plot_colours_each_bond_point_with_a_legend(cracked):
    path, _, state = cracked
    c = state.contacts
    counts = {s: int((bond_states(c.law[: c.count], c.damage[: c.count],
                                  c.history[: c.count], np.array([LawKind.COHESIVE])) == s).sum())
              for s in ("intact", "damaged", "cracked")}
    with Results(path) as r:
        fig = plot_frame(r, -1)
    assert isinstance(fig, Figure)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    for state_name, n in counts.items():
        assert (f"{state_name} bond ({n})" in labels) == (n > 0), labels
    assert counts["cracked"] >= 1 and counts["intact"] >= 1


def test_paraview_contacts_carry_the_damage(cracked, tmp_path):
    path, _, _ = cracked
    with Results(path) as r:
        pvd = export_vtk(r, tmp_path / "vtk")
        k = r.frame_count - 1
        c = r.contacts(k)
    mesh = meshio.read(pvd.parent / path.stem / f"contacts_{k:06d}.vtu")
    assert np.array_equal(mesh.point_data["damage"], c["damage"])
    assert np.array_equal(mesh.point_data["area"], c["area"])
    assert c["damage"].max() >= 1.0  # the crack is there (damage is clipped to [0, 1])


def _box(x0, x1, z0, z1) -> list[tuple[float, float, float]]:
    return [(x, y, z) for x in (x0, x1) for y in (0.0, 0.5) for z in (z0, z1)]


def test_3d_plot_colours_each_bond_point_with_a_legend(tmp_path):
    """3D: the column of _column as 0.5 m cubes, until its base joint cracks at a point."""
    law = sx.ContactLaw(friction=0.6, kind=LawKind.COHESIVE, k_n=1e10, k_t=4e9, f_t=1e5,
                        cohesion=5e5, g_i=10.0, g_ii=100.0)
    b = sx.ModelBuilder(dim=3)
    b.add_block(_box(-1.0, 1.0, -0.5, 0.0), kind=sx.BodyKind.FIXED, group="base")
    for k in range(2):
        b.add_block(_box(0.0, 0.5, 0.5 * k, 0.5 * (k + 1)), density=2000.0)
    b.set_law("block", "block", law)
    b.set_law("block", "base", law)
    b.add_force([2], lambda t: (2e6 * t, 0.0, 0.0, 0.0, 0.0, 0.0))
    model = b.finalize()
    sim = sx.Simulation(model, dt=DT)
    state = sim.initial_state()
    path = tmp_path / "column3d.h5"
    with ResultsWriter(path, model, dt=DT, theta=sim.integrator.theta) as w:
        while not (state.contacts.damage[: state.contacts.count] >= 1.0).any():
            sim.step(state)
            assert state.time < 0.05, "the base joint did not crack"
        w.write_frame(state)
    c = state.contacts
    states = bond_states(c.law[: c.count], c.damage[: c.count], c.history[: c.count],
                         model.law_kind)
    with Results(path) as r:
        fig = plot_frame(r, -1)
    labels = [t.get_text() for t in fig.axes[0].get_legend().get_texts()]
    for name in ("intact", "damaged", "cracked"):
        n = int((states == name).sum())
        assert (f"{name} bond ({n})" in labels) == (n > 0), labels
    assert (states == "cracked").any() and (states == "intact").any()
