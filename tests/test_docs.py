"""The documentation: the Python examples of README.md and docs/*.md run as written, the docs
index links every page, docs/structures.md describes every generator and the script that
draws its pictures runs and draws them all."""

import importlib.util
import re
from pathlib import Path

import numpy as np
import pytest
from PIL import Image

import saxum.structures

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
PAGES = [ROOT / "README.md", *sorted(DOCS.glob("*.md"))]
SNIPPETS = [(page, k, code) for page in PAGES
            for k, code in enumerate(re.findall(r"```python\n(.*?)```", page.read_text(),
                                                re.S))]


@pytest.mark.parametrize(("page", "k", "code"), SNIPPETS,
                         ids=[f"{p.name}-{k}" for p, k, _ in SNIPPETS])
def test_python_examples_run_as_written(page, k, code, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # files they write land here
    exec(compile(code, f"{page.name}, python block {k + 1}", "exec"), {})


def test_docs_index_links_every_page_and_every_link_resolves():
    index = (DOCS / "README.md").read_text()
    for page in DOCS.glob("*.md"):
        if page.name != "README.md":
            assert f"]({page.name}" in index, f"docs/README.md does not link {page.name}"
    for page in PAGES:
        for target in re.findall(r"\]\(([^)#:]+)(?:#[^)]*)?\)", page.read_text()):
            assert (page.parent / target).exists(), f"{page.name} links a missing {target}"


def test_structures_page_names_every_generator_and_shows_every_picture():
    page = (DOCS / "structures.md").read_text()
    for name in saxum.structures.__all__:
        assert f"`{name}" in page, f"{name} is not in docs/structures.md"
    for picture in sorted((DOCS / "img").glob("structures-*.png")):
        assert f"(img/{picture.name})" in page, picture.name


def test_gallery_script_draws_every_picture(tmp_path):
    spec = importlib.util.spec_from_file_location("gallery", DOCS / "structures_gallery.py")
    gallery = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(gallery)
    paths = gallery.main(tmp_path)
    assert [p.name for p in paths] == [f"structures-{n}.png" for n in gallery.PICTURES]
    for path in paths:
        assert Image.open(path).format == "PNG"
        assert (DOCS / "img" / path.name).is_file()  # the committed picture it replaces


# -- documented numbers, rerun ----------------------------------------------------------------
# Each number the docs state that a run reproduces in under a minute on the project's 2-core
# machine, read from its page and compared with a rerun within the tolerance the page states
# (the rest are marked "not rerun in CI" on their pages: docs/applications.md, docs/flood.md).

EXAMPLES = ROOT / "examples"


def _documented(page: Path, pattern: str) -> tuple[str, ...]:
    """The groups of `pattern` in `page` (whitespace in the pattern matches any, so that a
    sentence may wrap); fails when the page no longer says it."""
    match = re.search(pattern.replace(" ", r"\s+"), page.read_text())
    assert match, f"{page.name} no longer states {pattern!r}: update tests/test_docs.py"
    return match.groups()


def _static_factor(scenario: Path, overrides=()) -> tuple[float, float]:
    """The bracket (stands, collapses) of the horizontal load factor [-] that `saxum collapse
    SCENARIO --vary loads.horizontal_acceleration` finds (default tolerance, 0.5 %)."""
    from saxum.collapse import scenario_critical_value

    result = scenario_critical_value(scenario, "loads.horizontal_acceleration", 0.5, 5.0,
                                     overrides=tuple(overrides))
    return result.stands / 9.81, result.collapses / 9.81


def _in_bracket(documented: str, bracket: tuple[float, float]) -> bool:
    """A value written with n decimals lies in the bracket once rounded: within half a unit
    of its last digit of [stands, collapses]."""
    half = 0.5 * 10.0 ** -len(documented.split(".")[1])
    return bracket[0] - half <= float(documented) <= bracket[1] + half


@pytest.mark.parametrize(("page", "pattern", "scenario", "overrides"), [
    (ROOT / "README.md", r"horizontal collapse load factor \((0\.\d+)\)", "arch.toml", ()),
    (DOCS / "applications.md", r"\| static \(horizontal load factor\) \| (0\.\d+) \| \| -66",
     "shake_table_arch.toml", ("loads.ground_motion.amplitude=0.0",)),
    (DOCS / "applications.md", r"\| static \(horizontal load factor\) \| (0\.\d+) \| the right "
     "pier", "burnum_harmonic.toml", ("loads.ground_motion=",)),
], ids=["README-arch", "applications-shake-table", "applications-burnum"])
def test_documented_static_load_factors(page, pattern, scenario, overrides):
    (value,) = _documented(page, pattern)
    bracket = _static_factor(EXAMPLES / scenario, overrides)
    assert _in_bracket(value, bracket), (value, bracket)


def test_documented_shake_table_point_at_one_second():
    """The 1 s row of the shaking-table table (docs/applications.md: bisection to 2 %, angles
    rounded to the degree)."""
    import importlib.util

    amplitude, _, hinges = _documented(
        DOCS / "applications.md", r"\| 1 \| (0\.\d+) \| ([\d.]+) \| ([-\d, ]+) \|")
    spec = importlib.util.spec_from_file_location("shake", EXAMPLES / "shake_table_arch.py")
    shake = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(shake)
    from saxum.collapse import DYNAMIC_FRACTION, CollapseCriterion, collapse_curve

    (point,) = collapse_curve(shake.SCENARIO, (1.0,), 0.5, 25.0, tolerance=0.02,
                              criterion=CollapseCriterion(duration=2.0,
                                                          fraction=DYNAMIC_FRACTION))
    assert _in_bracket(amplitude, (point.stands / 9.81, point.collapses / 9.81))
    documented = sorted(float(a) for a in hinges.split(","))
    assert shake.hinge_angles(point.mechanism) == pytest.approx(documented, abs=1.0)


def test_documented_start_of_large_motion_of_the_burnum_ramp(tmp_path):
    """docs/applications.md: under the ramp, a free block first moves by more than ONSET x
    the collapse displacement within the documented bracket, give or take one output
    interval (0.05 s), as the page says."""
    from saxum.cli import main
    from saxum.collapse import DYNAMIC_FRACTION, ONSET
    from saxum.results import Results

    lo, hi = map(float, _documented(
        DOCS / "applications.md", r"\*\*Large motion begins at t = ([\d.]+)-([\d.]+) s"))
    out = tmp_path / "burnum.h5"
    assert main(["run", str(EXAMPLES / "burnum_harmonic.toml"), "--quiet", "-o", str(out),
                 "--set", f"output.duration={hi + 0.5}"]) == 0
    with Results(out) as r:
        free = r.model["body_kind"] == 0
        moved = np.linalg.norm(r.body_q[:, free, :2] - r.model["body_q0"][free, :2],
                               axis=-1).max(axis=1)
        limit = ONSET * DYNAMIC_FRACTION * float(r.body_size[free].min())
        began = float(r.time[np.argmax(moved > limit)])
        interval = float(r.time[1] - r.time[0])
    assert moved.max() > limit
    assert lo - interval - 1e-9 <= began <= hi + interval + 1e-9


def test_documented_start_of_the_parapet_slide_in_the_rising_flood(tmp_path, capsys):
    """docs/flood.md: the upstream parapet starts to slide between two output frames, and
    saxum info says the collapsing motion began then, with the parapet's joint sliding."""
    from saxum.cli import main

    lo, hi = _documented(DOCS / "flood.md",
                         r"parapet starts to slide between t = ([\d.]+) and ([\d.]+) s")
    out = tmp_path / "rising.h5"
    assert main(["run", str(EXAMPLES / "flood_bridge_rising.toml"), "--quiet", "-o", str(out),
                 "--set", "output.duration=16"]) == 0
    capsys.readouterr()
    assert main(["info", str(out)]) == 0
    report = capsys.readouterr().out
    began = float(re.search(r"when the collapsing motion began, t = ([\d.]+) s", report)[1])
    assert float(lo) < began <= float(hi) + 1e-9
    assert "sliding joint between upstream wall c6 and upstream parapet" in report
