"""The documentation: the Python examples of README.md and docs/*.md run as written, the docs
index links every page, docs/structures.md describes every generator and the script that
draws its pictures runs and draws them all."""

import importlib.util
import re
from pathlib import Path

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
