"""saxum.limit: the programme's duality, the non-associative iteration, bad input, the CLI.
(Validation against closed forms: tests/validation/test_limit_analysis.py.)"""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

import saxum as sx
from saxum.cli import main
from saxum.errors import InputError
from saxum.limit import _loads, limit_analysis, stands, static_critical_value
from saxum.model import BodyKind
from saxum.structures import semicircular_arch, wall

ARCH = Path(__file__).resolve().parents[1] / "examples" / "arch.toml"
NINE = ["structure.radius=1.0", "structure.thickness=0.15", "structure.voussoirs=9",
        "laws[0].friction=0.8", "laws[1].friction=0.8"]
"""The 9-voussoir arch of issue 17 from the example arch."""


def _virtual_work(result) -> float:
    """-D . u / L . u with the result's velocities: the kinematic factor of its mechanism."""
    dead, live, _ = _loads(result.model, "horizontal", 1.0)
    u = result.velocity
    return float(-(dead * u).sum() / (live * u).sum())


@pytest.mark.parametrize("model", [
    semicircular_arch(radius=1.0, thickness=0.15, voussoirs=15, friction=0.8),
    semicircular_arch(radius=1.0, thickness=0.3, voussoirs=15, friction=0.45),
    wall(courses=6, bricks=3, friction=0.5)])
def test_the_mechanism_does_the_work_of_the_factor(model):
    """Strong duality: the static factor equals the virtual work ratio of the dual's
    velocities (to the programme's tolerance, 1e-9 of the loads)."""
    result = limit_analysis(model)
    assert _virtual_work(result) == pytest.approx(result.factor, rel=1e-7)
    # the associative flow rule: every contact opens or slides with dilatancy, none closes
    rel = result.relative
    slip = np.abs(rel[:, 0])
    assert (rel[:, 1] >= result.model.law_friction[result.contacts.law[:len(rel)]] * slip
            - 1e-7).all()


def test_point_loads_as_the_live_load():
    """live="forces": a point load on the fifth voussoir times lambda; the mechanism does its
    work (duality, as above) with four hinges, one at a joint of the loaded voussoir."""
    from saxum.structures.arch import add_supported_semicircular_arch

    builder = sx.ModelBuilder()
    ids = add_supported_semicircular_arch(builder, radius=1.0, thickness=0.15, voussoirs=15)
    builder.set_law("voussoir", "voussoir", sx.ContactLaw(friction=0.8))
    builder.set_law("voussoir", "support", sx.ContactLaw(friction=0.8))
    builder.add_force([ids[4]], lambda t: (0.0, -1000.0, 0.0))
    model = builder.finalize()
    result = limit_analysis(model, live="forces")
    dead, live, _ = _loads(model, "forces", 1.0)
    u = result.velocity
    assert -(dead * u).sum() / (live * u).sum() == pytest.approx(result.factor, rel=1e-7)
    assert len(result.mechanism.hinges) == 4
    assert any("voussoir 5" in j.bodies for j in result.mechanism.hinges)


def test_the_non_associative_iteration_ends_coulomb_admissible_and_not_dilatant():
    model = wall(courses=6, bricks=3, friction=0.5)
    assoc = limit_analysis(model)
    result = limit_analysis(model, friction="non-associative")
    assert result.factor <= assoc.factor * (1 + 1e-9)
    mu = model.law_friction[result.contacts.law[:result.contacts.count]]
    assert (np.abs(result.force[:, 0]) <= mu * result.force[:, 1] + 1e-7 * result.force.max()
            ).all()
    assert result.mechanism.sliding
    rel = result.relative
    sliding = (np.abs(rel[:, 0]) > 1e-6) & (result.force[:, 1] > 1e-9 * result.force.max())
    assert np.abs(rel[sliding, 1]) == pytest.approx(0.0, abs=1e-7)  # no dilatancy


def _two_blocks(lift: float) -> sx.Model:
    builder = sx.ModelBuilder()
    builder.add_block([(-1.0, -0.2), (1.0, -0.2), (1.0, 0.0), (-1.0, 0.0)],
                      kind=BodyKind.FIXED, group="ground", name="ground")
    builder.add_block([(0.0, 0.0), (0.4, 0.0), (0.4, 1.0), (0.0, 1.0)], density=2000.0,
                      group="block", name="pier")
    builder.add_block([(0.5, lift), (0.7, lift), (0.7, lift + 0.2), (0.5, lift + 0.2)],
                      density=2000.0, group="block", name="loose stone")
    builder.set_law("ground", "block", sx.ContactLaw(friction=0.6))
    builder.set_law("block", "block", sx.ContactLaw(friction=0.6))
    return builder.finalize()


def test_a_free_block_touching_nothing_is_named():
    with pytest.raises(InputError, match="touching nothing.*loose stone"):
        limit_analysis(_two_blocks(0.5))


def test_a_structure_that_falls_under_its_weight_is_named():
    builder = sx.ModelBuilder()
    builder.add_block([(-1.0, -0.2), (1.0, -0.2), (1.0, 0.0), (-1.0, 0.0)],
                      kind=BodyKind.FIXED, group="ground", name="ground")
    builder.add_block([(0.0, 0.0), (0.2, 0.0), (0.2, 0.2), (0.0, 0.2)], density=2000.0,
                      group="block", name="pier")
    builder.add_block([(0.1, 0.2), (1.0, 0.2), (1.0, 0.3), (0.1, 0.3)], density=2000.0,
                      group="block", name="overhang")
    builder.set_law("ground", "block", sx.ContactLaw(friction=0.6))
    builder.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = builder.finalize()
    with pytest.raises(InputError, match="cannot stand under its dead load.*overhang"):
        limit_analysis(model)
    assert not stands(model)


def test_a_load_that_cannot_cause_collapse_is_said_so():
    model = _two_blocks(0.0)
    down = np.zeros((model.body_count, 3))
    down[1, 1] = -1000.0  # pressing the pier onto the ground
    with pytest.raises(InputError, match="cannot cause collapse.*pier"):
        limit_analysis(model, live=down)


def test_the_static_verdict_follows_the_loads():
    model = semicircular_arch(radius=1.0, thickness=0.15, voussoirs=9, friction=0.8)
    factor = limit_analysis(model).factor
    g = 9.81
    for f, standing in ((0.999 * factor, True), (1.001 * factor, False)):
        loaded = dataclasses.replace(model, accelerations=((lambda t, a=f * g: (a, 0.0)),))
        assert stands(loaded) == standing


def test_cli_limit_prints_the_factor_and_draws_the_mechanism(tmp_path, capsys):
    sets = [a for s in NINE for a in ("--set", s)]
    assert main(["limit", str(ARCH), *sets, "-o", str(tmp_path / "m.png")]) == 0
    out = capsys.readouterr().out
    assert "limit load factor lambda = 0.147381" in out
    assert out.count("hinge between") == 4
    assert Path(tmp_path / "m.png").stat().st_size > 0


def test_cli_limit_refuses_a_ground_motion(capsys):
    path = ARCH.parent / "shake_table_arch.toml"
    assert main(["limit", str(path)]) == 2
    assert "constant loads" in capsys.readouterr().err


def test_static_critical_thickness():
    t = static_critical_value(ARCH, "structure.thickness", 0.15, 0.05, overrides=tuple(NINE),
                              tolerance=1e-4)
    assert stands(semicircular_arch(radius=1.0, thickness=t * 1.001, voussoirs=9,
                                    friction=0.8))
    assert not stands(semicircular_arch(radius=1.0, thickness=t * 0.999, voussoirs=9,
                                        friction=0.8))


SPREADING = """\
[structure]
type = "arch"
shape = "semicircular"
span = 1.85
thickness = 0.15
voussoirs = 30

[[laws]]
groups = ["*", "*"]
friction = 1.0

[[loads.settlements]]
block = "right pier c1"
magnitude = 0.01
direction = [1.0, 0.0]

[output]
duration = 1.0
"""


def test_cli_limit_settlement_finds_the_least_thrust_and_its_three_hinges(tmp_path, capsys):
    """--live settlement: the right abutment of a semicircular arch (R = 1 m, t = 0.15 m)
    moves outward at 0.01 m/s; the power on it is the minimum thrust times 0.01 m/s (the
    thrust checked against the ring's equilibrium in
    tests/validation/test_limit_loads.py), with three hinges."""
    path = tmp_path / "spreading.toml"
    path.write_text(SPREADING)
    assert main(["limit", str(path), "--live", "settlement", "-o",
                 str(tmp_path / "m.png")]) == 0
    out = capsys.readouterr().out
    assert "settled supports: the structure's forces on them do" in out
    assert out.count("hinge between") == 3
    assert main(["limit", str(path), "--live", "water"]) == 2
    assert "analyse the settlements with --live settlement" in capsys.readouterr().err


def test_settlement_input_is_checked():
    model = semicircular_arch(radius=1.0, thickness=0.15, voussoirs=9, friction=0.8)
    with pytest.raises(InputError, match="give both or neither"):
        limit_analysis(model, live="settlement")
    with pytest.raises(InputError, match="no block called 'pier'"):
        limit_analysis(model, live="settlement", settlement={"pier": (1.0, 0.0, 0.0)})
    with pytest.raises(InputError, match="'voussoir 1' is a free block"):
        limit_analysis(model, live="settlement", settlement={"voussoir 1": (1.0, 0.0, 0.0)})
    with pytest.raises(InputError, match="must be 3 finite numbers"):
        limit_analysis(model, live="settlement", settlement={"support": (1.0, 0.0)})
    with pytest.raises(InputError, match="has none on its free blocks"):
        limit_analysis(model, live="water")


def test_a_settlement_that_nothing_bounds_is_said_so():
    """A rigid block between two walls that close on it: its forces on them can be as large
    as any (rigid, no crushing), so the least power is unbounded."""
    builder = sx.ModelBuilder()
    for name, (x0, x1, y0, y1) in (("ground", (-1.0, 2.0, -0.2, 0.0)),
                                   ("left", (-0.5, 0.0, 0.0, 1.0)),
                                   ("right", (0.4, 0.9, 0.0, 1.0))):
        builder.add_block([(x0, y0), (x1, y0), (x1, y1), (x0, y1)], kind=BodyKind.FIXED,
                          group="support", name=name)
    builder.add_block([(0.0, 0.0), (0.4, 0.0), (0.4, 0.5), (0.0, 0.5)], density=2000.0,
                      group="block", name="block")
    builder.set_law("support", "block", sx.ContactLaw(friction=0.6))
    builder.set_law("block", "block", sx.ContactLaw(friction=0.6))
    model = builder.finalize()
    with pytest.raises(InputError, match=r"supports' motion \(right\) finds no bound"):
        limit_analysis(model, live="settlement", settlement={"right": (-1.0, 0.0, 0.0)})
    opening = limit_analysis(model, live="settlement", settlement={"right": (1.0, 0.0, 0.0)})
    # it leaves the block: no force, to the programme's tolerance, 1e-9 of the weight 3924 N/m
    assert opening.support_power == pytest.approx(0.0, abs=4e-6)


def test_the_3d_mechanism_is_drawn(tmp_path):
    """plot_limit_3d: the extruded arch's four hinge lines, the blocks moved by their
    virtual velocities; a 2D result is refused with the function to use."""
    from saxum.plot3d import plot_limit_3d
    from saxum.structures.solid import extruded

    flat = semicircular_arch(radius=1.0, thickness=0.15, voussoirs=9, friction=0.8)
    result = limit_analysis(extruded(flat, 0.5))
    fig = plot_limit_3d(result, tmp_path / "m.png", title="arch")
    (ax,) = [a for a in fig.axes if a.name == "3d"]
    assert len([line for line in ax.lines if line.get_linewidth() == 3.0]) == 4
    assert "limit load factor" in ax.get_title()
    assert (tmp_path / "m.png").stat().st_size > 0
    with pytest.raises(InputError, match="plot.plot_limit draws 2D"):
        plot_limit_3d(limit_analysis(flat))


def test_cli_limit_draws_a_3d_mechanism(tmp_path, capsys):
    path = tmp_path / "barrel.toml"
    path.write_text('[structure]\ntype = "semicircular_arch_3d"\nradius = 1.0\n'
                    'thickness = 0.15\nvoussoirs = 9\ndepth = 0.5\n\n[[laws]]\n'
                    'groups = ["*", "*"]\nfriction = 0.8\n\n[output]\nduration = 1.0\n')
    assert main(["limit", str(path), "-o", str(tmp_path / "m.png")]) == 0
    assert "limit load factor lambda = 0.1473" in capsys.readouterr().out  # the 2D 0.147381
    assert (tmp_path / "m.png").stat().st_size > 0
