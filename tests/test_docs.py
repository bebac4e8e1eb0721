"""docs/structures.md: every generator is described, and the script that draws its pictures
runs and draws them all."""

import importlib.util
from pathlib import Path

from PIL import Image

import saxum.structures

DOCS = Path(__file__).resolve().parents[1] / "docs"


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
