"""A stone arch bridge under a rising flood, in 3D: the whole single-span bridge (after Rafiee
& Vinches 2013, Engineering Structures 48, 739-749; geometry and loads assumed, see
docs/flood.md, "In 3D: the whole bridge").

The bridge of flood_bridge3d.toml runs along x; the river flows through the arch along +y,
across the bridge, so the upstream face is y = 0: the barrel's ring, the spandrel wall and the
parapet on it meet the flow. The cross-section of the walls, fill and parapets is that of the
2D section through a pier (flood_bridge.py): walls 0.7 m thick, the road 7 m above the river
bed, parapets 0.4 x 1.0 m, stone 2400 and fill 2000 kg/m^3, friction 0.6, C_d = 1.4.

Run: python examples/flood_bridge3d.py   (finds by bisection the level or the velocity at
                                           failure in three cases, prints the mechanisms and
                                           the statics, draws each case failing to
                                           flood-bridge3d-<tag>.png)
     option: --out DIR (where the pictures go: default the current directory; the docs'
             pictures: --out docs/img)
"""

import math
import tempfile
from pathlib import Path

import numpy as np

from saxum.collapse import CollapseCriterion, critical_value
from saxum.results import Results
from saxum.runner import run_scenario
from saxum.scenario import load_scenario

HERE = Path(__file__).resolve().parent
SCENARIO = HERE / "flood_bridge3d.toml"
DECK = 7.0  # the road above the river bed [m] (abutment_height + spandrel_height)
G, RHO_W, MU, CD = 9.81, 1000.0, 0.6, 1.4

CASES = {
    # name: (key varied, stands at, collapses at, other overrides, parapets, picture tag)
    "rising level, flow 3 m/s": ("loads.flood.level", 6.0, 9.0, [], True, "level"),
    "rising flow, water 1 m over the road": ("loads.flood.velocity", 0.5, 4.0,
                                             [f"loads.flood.level={DECK + 1.0}"], True,
                                             "velocity"),
    "parapets gone, water 1 m over the road": ("loads.flood.velocity", 4.0, 10.0,
                                               [f"loads.flood.level={DECK + 1.0}"], False,
                                               "no-parapets"),
}

# At rest means every block at rest (per-block rest test, as in 2D: docs/flood.md).
CRITERION = CollapseCriterion(duration=1.0)


def scenario(overrides, parapets: bool = True):
    """The scenario of flood_bridge3d.toml with `overrides` ("key=value"), without its
    parapets if not `parapets`."""
    sc = load_scenario(SCENARIO, overrides)
    if parapets:
        return sc
    bare = sc.structure.model_copy(update={"parapet_thickness": None, "parapet_height": None})
    return sc.model_copy(update={"structure": bare})


def parapet_statics(level: float | None = None, velocity: float | None = None) -> dict:
    """The upstream parapet (t x h, rho_s, on the road at DECK) as a rigid block under drag
    p_d = 1/2 rho_w C_d U^2 on its wet height d and buoyancy rho_w g t d, per metre of its
    length: it slides when p_d d = mu g (rho_s t h - rho_w t d) and overturns about its
    downstream toe when p_d d^2/2 = g (rho_s t h - rho_w t d) t/2. Given the velocity U
    [m/s]: the levels [m] of each; given the level: the velocities [m/s]."""
    structure = load_scenario(SCENARIO).structure
    t, h, rho_s = structure.parapet_thickness, structure.parapet_height, structure.density
    if velocity is not None:
        p = 0.5 * RHO_W * CD * velocity**2
        slide = MU * G * rho_s * t * h / (p + MU * G * RHO_W * t)
        a = G * RHO_W * t * t / 2  # p d^2/2 + a d - g rho_s t h t/2 = 0
        overturn = (-a + math.sqrt(a * a + 2 * p * G * rho_s * t * h * t / 2)) / p
        return {"slides": DECK + slide, "overturns": DECK + overturn}
    d = level - DECK
    weight = G * (rho_s * t * h - RHO_W * t * d)  # [N/m] submerged
    return {"slides": math.sqrt(MU * weight / d / (0.5 * RHO_W * CD)),
            "overturns": math.sqrt(weight * t / d**2 / (0.5 * RHO_W * CD))}


def superstructure(level: float = DECK + 1.0) -> tuple[float, float]:
    """Without parapets, under water at `level` [m]: the submerged weight W' [N] of the
    barrel, spandrel walls and fill (everything above the springing plane) and the area A
    [m^2] of their elevation (the drag's area), from the blocks' own volumes and faces."""
    model = scenario([f"loads.flood.level={level}"], parapets=False).build_simulation().model
    group = [model.group_names[g] for g in model.body_group]
    above = [b for b in range(model.body_count) if group[b] in ("voussoir", "spandrel", "fill")]
    volume = {b: model.body_mass[b] / model.body_density[b] for b in above}
    weight = sum(G * (model.body_mass[b] - RHO_W * volume[b]) for b in above)
    width = load_scenario(SCENARIO).structure.width
    area = sum(volume[b] for b in above if group[b] == "voussoir") / width
    area += sum(volume[b] / np.ptp(model.vertices(b)[:, 1])
                for b in above if model.body_name[b].endswith(" y0"))  # the upstream wall
    return float(weight), float(area)


def sliding_velocity(thrusts=(), normals=()) -> float:
    """Without parapets, 1 m of water over the road: the velocity [m/s] at which everything
    above the springing plane slides on it. With friction carrying the drag alone,
    1/2 rho_w C_d U^2 A = mu W' (an upper bound); given the thrust H_i [N] and normal force
    N_i [N] on each abutment, the friction there carries both, |(H_i, D_i)| = mu N_i, and
    1/2 rho_w C_d U^2 A = sum_i sqrt((mu N_i)^2 - H_i^2)."""
    weight, area = superstructure()
    resisted = (sum(math.sqrt((MU * n) ** 2 - h**2) for h, n in zip(thrusts, normals,
                                                                    strict=True))
                if thrusts else MU * weight)
    return math.sqrt(resisted / (0.5 * RHO_W * CD * area))


def springing_forces(trial) -> list[tuple[float, float, float]]:
    """The force [N] (x, y, z) the superstructure exerts on each abutment in the final state
    of a collapse trial (saxum.collapse.Trial): the contact forces on the abutment from every
    body but the river bed, in world axes."""
    model, state = trial.simulation.model, trial.state
    c = state.contacts
    k = c.count
    world = np.einsum("ci,cij->cj", c.impulse[:k], c.frame[:k]) / trial.simulation.integrator.dt
    forces = []
    for b in (i for i, name in enumerate(model.body_name) if "abutment" in name):
        ground = model.body_name.index("ground")
        on = (c.candidate[:k] == b) & (c.antagonist[:k] != ground)
        by = (c.antagonist[:k] == b) & (c.candidate[:k] != ground)
        forces.append(tuple(map(float, world[on].sum(axis=0) - world[by].sum(axis=0))))
    return forces


def main(tolerance: float = 0.005, cases=tuple(CASES), pictures: Path | None = None) -> dict:
    """For each case bisect on the flood parameter; prints and returns {case:
    (CriticalValue, Mechanism)}; draws each case failing, 0.6 s after the start of the trial
    just above the critical value, to the folder `pictures` if given
    (flood-bridge3d-<tag>.png)."""
    found = {}
    for name in cases:
        key, stands, collapses, others, parapets, tag = CASES[name]
        result = critical_value(
            lambda x, k=key, o=others, p=parapets: scenario([*o, f"{k}={x!r}"], p)
            .build_simulation(), stands, collapses, tolerance=tolerance, criterion=CRITERION)
        mech = result.collapse().mechanism()
        unit = "m" if key.endswith("level") else "m/s"
        print(f"{name}: {key} at failure {result.value:.3f} {unit} (stands at "
              f"{result.stands:.3f}, collapses at {result.collapses:.3f}; "
              f"{len(result.trials)} trials)\nmoving blocks: {', '.join(mech.moving)}")
        found[name] = (result, mech)
        if pictures is not None:
            _picture(scenario([*others, f"{key}={result.collapses!r}", "output.duration=0.6",
                               "output.interval=0.6"], parapets),
                     f"{name}: {key.split('.')[-1]} {result.collapses:.2f} {unit}",
                     pictures / f"flood-bridge3d-{tag}.png")
    if "rising level, flow 3 m/s" in found:
        print("statics, parapet under 3 m/s:", parapet_statics(velocity=3.0))
    if "rising flow, water 1 m over the road" in found:
        print("statics, parapet under 1 m of water:", parapet_statics(level=DECK + 1.0))
    if "parapets gone, water 1 m over the road" in found:
        print(f"statics, one sliding plane at the springing, thrust ignored: "
              f"{sliding_velocity():.3f} m/s")
        result = found["parapets gone, water 1 m over the road"][0]
        stood = next(t for t in reversed(result.trials) if t.value == result.stands)
        forces = springing_forces(stood)
        for fx, fy, fz in forces:
            print(f"on an abutment at {result.stands:.3f} m/s: thrust {fx / 1e3:.1f} kN, drag "
                  f"share {fy / 1e3:.1f} kN, normal {-fz / 1e3:.1f} kN: friction used "
                  f"{math.hypot(fx, fy) / (MU * abs(fz)):.4f} of mu N")
        print(f"statics with these thrusts and normal forces: "
              f"{sliding_velocity([f[0] for f in forces], [-f[2] for f in forces]):.3f} m/s")
    return found


def _picture(sc, title: str, path: Path) -> None:
    """The scenario run for its duration, its last frame drawn to `path` (plot_frame_3d:
    blocks coloured by displacement, the water's surface and the flow)."""
    from saxum.plot3d import plot_frame_3d

    with tempfile.TemporaryDirectory() as tmp:
        run_scenario(sc, Path(tmp) / "run.h5", quiet=True)
        with Results(Path(tmp) / "run.h5") as results:
            plot_frame_3d(results, -1, path, forces=False, title=title, figsize=(7.0, 6.0),
                          dpi=100)


def cli(argv: list[str] | None = None) -> dict:
    """The command line (module doc): pictures go to the current directory unless --out."""
    import argparse

    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--out", type=Path, default=Path(),
                        help="folder of the pictures (default: the current directory)")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    return main(pictures=args.out)


if __name__ == "__main__":
    cli()
