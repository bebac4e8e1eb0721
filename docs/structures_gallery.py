"""The pictures of docs/structures.md: one model from every generator of saxum.structures, at
its initial position (saxum.plot.plot_model).

    python docs/structures_gallery.py [FOLDER]     # default: docs/img

writes structures-arches.png, structures-walls.png, structures-piers.png,
structures-bridges.png and structures-blocks.png into FOLDER.
"""

import math
import sys
import tempfile
from pathlib import Path

from matplotlib.figure import Figure

from saxum import BodyKind
from saxum.plot import plot_model
from saxum.structures import (
    ArchShape,
    Opening,
    arch,
    arch_bridge,
    blocks_model,
    buttressed_wall,
    pier,
    semicircular_arch,
    wall,
)

PICTURES = ("arches", "walls", "piers", "bridges", "blocks")

# An irregular dry-stone pier of six stones on a footing, as a CSV file would give it [m].
STONES = """block,x,y,kind,group
footing,-0.6,-0.2,fixed,ground
footing,1.4,-0.2,,
footing,1.4,0,,
footing,-0.6,0,,
s1,0,0,,stone
s1,0.45,0,,
s1,0.5,0.3,,
s1,0,0.28,,
s2,0.45,0,,stone
s2,0.8,0,,
s2,0.8,0.32,,
s2,0.5,0.3,,
s3,0,0.28,,stone
s3,0.5,0.3,,
s3,0.42,0.55,,
s3,0.05,0.6,,
s4,0.5,0.3,,stone
s4,0.8,0.32,,
s4,0.78,0.6,,
s4,0.42,0.55,,
s5,0.05,0.6,,stone
s5,0.42,0.55,,
s5,0.78,0.6,,
s5,0.7,0.85,,
s5,0.1,0.85,,
"""


def _grid(panels, columns: int, path: Path, size: tuple[float, float] = (4.2, 3.3)) -> None:
    """Save (model, title) panels on a grid of `columns` columns, each `size` [in]."""
    rows = math.ceil(len(panels) / columns)
    fig = Figure(figsize=(size[0] * columns, size[1] * rows), layout="constrained")
    axes = fig.subplots(rows, columns, squeeze=False).ravel()
    for ax, (model, title) in zip(axes, panels, strict=False):
        plot_model(model, ax=ax, title=title)
    for ax in axes[len(panels):]:
        ax.set_axis_off()
    fig.savefig(path, dpi=110)


def main(folder: str | Path = Path(__file__).parent / "img") -> list[Path]:
    """Write the pictures into `folder`; returns their paths."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    paths = {name: folder / f"structures-{name}.png" for name in PICTURES}

    _grid([
        (semicircular_arch(radius=1.0, thickness=0.2, voussoirs=11),
         "semicircular_arch: R = 1 m, t = 0.2 m, 11 voussoirs"),
        (arch(ArchShape.segmental(span=4.0, rise=1.0, thickness=0.35), voussoirs=11),
         "segmental: span 4 m, rise 1 m, t = 0.35 m"),
        (arch(ArchShape.segmental(span=4.0, rise=1.0, thickness=0.35), voussoirs=11,
              joints="vertical"), "segmental, vertical joints"),
        (arch(ArchShape.pointed(span=2.0, thickness=0.25, eccentricity=1.0), voussoirs=12,
              pier_width=0.6, pier_height=1.2, pier_courses=3, pier_kind=BodyKind.FREE),
         "pointed (e = 1) on free piers of 3 courses"),
        (arch(ArchShape.elliptical(span=4.0, rise=1.2, thickness=0.3), voussoirs=13),
         "elliptical: span 4 m, rise 1.2 m"),
        (arch(ArchShape.basket_handle(span=4.0, rise=1.2, thickness=0.3), voussoirs=13),
         "basket_handle: span 4 m, rise 1.2 m"),
        (arch(ArchShape.circular(span=3.0, thickness=0.3, embrace=math.radians(140.0)),
              voussoirs=11), "circular: embrace 140 degrees"),
        (arch(ArchShape.flat(span=1.5, depth=0.35), voussoirs=7), "flat (jack) arch"),
        (arch(ArchShape.semicircular(span=2.0, thickness=0.3), voussoirs=11, rings=2,
              ring_stagger=True), "2 rings, staggered joints"),
        (arch(ArchShape.segmental(span=4.0, rise=1.0, thickness=0.45), voussoirs=[11, 13, 15],
              rings=3), "segmental in 3 rings, 11/13/15 voussoirs"),
    ], 4, paths["arches"])

    _grid([
        (wall(courses=16, bricks=12, openings=[
            Opening(0.5, 0.0, 0.75, 0.65),
            Opening(1.75, 0.325, 0.5, 0.39, head="segmental_arch", rise=0.12, voussoirs=7,
                    head_depth=0.13),
            Opening(2.5, 0.325, 0.25, 0.39, head="flat_arch", voussoirs=5,
                    head_depth=0.13)]),
         "wall: door with a lintel, windows with segmental and flat arches"),
        (wall(courses=10, bricks=8, bond="stack"), "wall: stack bond"),
        (wall(courses=10, bricks=8, half_bricks=False), "wall: running bond, toothed ends"),
    ], 1, paths["walls"], size=(8.0, 3.2))

    _grid([
        (pier(width=0.6, height=2.4, courses=6), "pier: 0.6 x 2.4 m, 6 courses"),
        (buttressed_wall(height=4.0, thickness=0.6, courses=10, buttress_width=1.2,
                         buttress_height=3.2, setbacks=2, block_length=0.4),
         "buttressed_wall: 2 setbacks"),
    ], 2, paths["piers"])

    shape = ArchShape.segmental(span=6.0, rise=2.0, thickness=0.5)
    _grid([
        (arch_bridge(shape, spans=3, voussoirs=13, pier_width=1.5, pier_height=3.0,
                     abutment_width=2.5), "arch_bridge: fill as a surcharge"),
        (arch_bridge(shape, spans=3, voussoirs=13, pier_width=1.5, pier_height=3.0,
                     abutment_width=2.5, fill="blocks", fill_depth=0.8, pier_courses=3),
         "arch_bridge: fill as blocks, piers of 3 courses"),
    ], 1, paths["bridges"], size=(9.0, 2.8))

    with tempfile.TemporaryDirectory() as tmp:
        stones = Path(tmp) / "stones.csv"
        stones.write_text(STONES)
        _grid([(blocks_model(stones, density=2300.0), "blocks_model: stones.csv")], 1,
              paths["blocks"], size=(5.0, 3.5))
    return list(paths.values())


if __name__ == "__main__":
    for path in main(*sys.argv[1:]):
        print(path)
