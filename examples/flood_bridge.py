"""A stone arch bridge under a rising flood (after Rafiee & Vinches 2013, Engineering
Structures 48, 739-749; geometry and loads assumed, see docs/flood.md).

The 2D section is the bridge cut across its width through the axis of a pier, in the plane of
the river's flow (which runs along +x, from the upstream cutwater to the downstream one): the
pier on the river bed, the two spandrel walls on it with the fill between them, and a parapet
on each spandrel wall. The section is written to flood-bridge-section.json, which the scenario
flood_bridge.toml reads; the flood there is still water at 2 m with a 3 m/s flow.

Run: python examples/flood_bridge.py    (writes the blocks, finds by bisection the level or
                                          the velocity at failure in four cases, prints the
                                          mechanisms, draws flood-bridge.png)
     options: --out DIR (where the picture and the blocks go: default the current directory;
              the docs' picture: --out docs/img --blocks examples/flood-bridge-section.json)
or:  saxum collapse examples/flood_bridge.toml --vary loads.flood.level --stands 4
         --collapses 9
"""

import itertools
from pathlib import Path

import saxum as sx
from saxum.collapse import CollapseCriterion, critical_value
from saxum.mechanism import mechanism
from saxum.plot import save_states
from saxum.structures.blockfile import write_blocks

HERE = Path(__file__).resolve().parent
SCENARIO = HERE / "flood_bridge.toml"
BLOCKS = HERE / "flood-bridge-section.json"

# Assumed geometry [m] (docs/flood.md): a bridge 5 m wide between the outer faces of its
# spandrel walls, on piers 4 m high with cutwaters 1.2 m (upstream) and 0.8 m (downstream)
# long, spandrel walls 0.7 m thick and 3 m high (springing to deck), parapets 0.4 x 1.0 m.
PIER_HEIGHT = 4.0
UPSTREAM_CUTWATER = 1.2
WIDTH = 5.0
DOWNSTREAM_CUTWATER = 0.8
SPANDREL_HEIGHT = 3.0
WALL = 0.7
PARAPET = (0.4, 1.0)
COURSE = 0.5  # course height
STONE_LENGTH = 1.5  # pier stones
FILL_LENGTH = 1.2  # fill "blocks" (rubble packed between the walls)
STONE, FILL = 2400.0, 2000.0  # densities [kg/m^3]
DECK = PIER_HEIGHT + SPANDREL_HEIGHT  # height of the road [m]


def _rectangle(x0, y0, x1, y1):
    return [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]


def _edges(x0, x1, length, shifted):
    """Head joints of a course from x0 to x1 [m], running bond (half a block offset)."""
    edges, k = [x0], 0.5 if shifted else 1.0
    while x0 + k * length < x1 - 0.25 * length:
        edges.append(x0 + k * length)
        k += 1.0
    return edges + [x1]


def add_section(b: sx.ModelBuilder, *, parapets: bool = True) -> None:
    """Add the transverse section through a pier to `b`, friction 0.6 on every joint."""
    b.add_block(_rectangle(-4.0, -1.0, 12.0, 0.0), kind=sx.BodyKind.FIXED, group="ground",
                name="river bed")
    x0, x1 = 0.0, UPSTREAM_CUTWATER + WIDTH + DOWNSTREAM_CUTWATER
    for c in range(round(PIER_HEIGHT / COURSE)):
        xs = _edges(x0, x1, STONE_LENGTH, c % 2 == 1)
        for k, (a, e) in enumerate(itertools.pairwise(xs)):
            b.add_block(_rectangle(a, c * COURSE, e, (c + 1) * COURSE), density=STONE,
                        group="stone", name=f"pier c{c + 1}s{k + 1}")
    up, down = UPSTREAM_CUTWATER, UPSTREAM_CUTWATER + WIDTH  # outer faces of the walls
    for c in range(round(SPANDREL_HEIGHT / COURSE)):
        y0, y1 = PIER_HEIGHT + c * COURSE, PIER_HEIGHT + (c + 1) * COURSE
        b.add_block(_rectangle(up, y0, up + WALL, y1), density=STONE, group="stone",
                    name=f"upstream wall c{c + 1}")
        xs = _edges(up + WALL, down - WALL, FILL_LENGTH, c % 2 == 1)
        for k, (a, e) in enumerate(itertools.pairwise(xs)):
            b.add_block(_rectangle(a, y0, e, y1), density=FILL, group="fill",
                        name=f"fill c{c + 1}b{k + 1}")
        b.add_block(_rectangle(down - WALL, y0, down, y1), density=STONE, group="stone",
                    name=f"downstream wall c{c + 1}")
    if parapets:
        t, h = PARAPET
        b.add_block(_rectangle(up, DECK, up + t, DECK + h), density=STONE, group="stone",
                    name="upstream parapet")
        b.add_block(_rectangle(down - t, DECK, down, DECK + h), density=STONE, group="stone",
                    name="downstream parapet")
    for pair in itertools.combinations_with_replacement(("ground", "stone", "fill"), 2):
        b.set_law(*pair, sx.ContactLaw(friction=0.6))


def section(*, parapets: bool = True) -> sx.Model:
    """The transverse section through a pier, at rest, without water."""
    b = sx.ModelBuilder()
    add_section(b, parapets=parapets)
    return b.finalize()


def simulation(flood: sx.FloodLoad, *, parapets: bool = True) -> sx.Simulation:
    """The section (with or without its parapets) under `flood`, dt = 1 ms."""
    b = sx.ModelBuilder()
    add_section(b, parapets=parapets)
    b.add_field_load(flood)
    return sx.Simulation(b.finalize(), dt=1e-3)


CASES = {
    # name: (parameter varied, stands at, collapses at, the other flood parameters, parapets)
    "rising level, flow 3 m/s": ("level", 4.0, 9.0, {"velocity": 3.0}, True),
    "rising flow, water 1 m over the deck": ("velocity", 0.5, 4.0, {"level": DECK + 1.0},
                                             True),
    "parapets gone, water 1 m over the deck": ("velocity", 1.0, 12.0, {"level": DECK + 1.0},
                                               False),
    "arches blocked by debris, tailwater at the springing": (
        "level", 4.5, 16.0, {"tailwater": PIER_HEIGHT}, False),
}

# At rest means every block at rest (the default, per_block): a rest test on the whole
# structure's net force would call a parapet that starts to overturn slowly "at rest", its net
# force being tiny next to the forces on the pier.
CRITERION = CollapseCriterion(duration=1.0)


def main(tolerance: float = 0.005, cases=tuple(CASES), picture: Path | None = None) -> dict:
    """For each case bisect on the flood parameter; prints and returns {case:
    (CriticalValue, Mechanism)}; draws the collapsing states to `picture` (PNG) if given."""
    found, panels = {}, []
    for name in cases:
        key, stands, collapses, others, parapets = CASES[name]
        result = critical_value(
            lambda x, k=key, o=others, p=parapets: simulation(sx.FloodLoad(**o, **{k: x}),
                                                              parapets=p),
            stands, collapses, tolerance=tolerance, criterion=CRITERION)
        trial = result.collapse()
        sim = trial.simulation
        sim.run(trial.state, 0.05)  # let the mechanism show
        mech = mechanism(sim.model, trial.state, sim.integrator.dt)
        unit = "m" if key == "level" else "m/s"
        print(f"{name}: {key} at failure {result.value:.3f} {unit} (stands at "
              f"{result.stands:.3f}, collapses at {result.collapses:.3f}; "
              f"{len(result.trials)} trials)\n{mech.text()}\n")
        found[name] = (result, mech)
        if picture is not None:
            sim.run(trial.state, 0.6)
            panels.append((sim.model, trial.state.body_q.copy(),
                           f"{name}:\n{key} {result.collapses:.2f} {unit}, t = "
                           f"{trial.state.time:.2f} s"))
    if picture is not None:
        save_states(picture, panels)
    return found


def cli(argv: list[str] | None = None) -> dict:
    """The command line (module doc): files go to the current directory unless --out."""
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path(),
                        help="folder of the picture (default: the current directory)")
    parser.add_argument("--blocks", type=Path, default=None,
                        help="the section's block file (default: in --out)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    write_blocks(args.blocks or args.out / BLOCKS.name, section())
    return main(picture=args.out / "flood-bridge.png")


if __name__ == "__main__":
    cli()
