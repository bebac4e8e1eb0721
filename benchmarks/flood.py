"""Benchmark of the flood loads (saxum.flood): what the water costs per time step.

    python benchmarks/flood.py [--json benchmarks/results/flood.json]

On the 1020-brick running-bond wall (40 courses of 25 bricks, 2.6 m high) with the water at
mid-height and a 2 m/s flow: the time of one evaluation of the flood load (hydrostatic
pressure on every edge + drag with shielding over all blocks), of the still-water part alone,
and of a whole time step of the wall at rest under the flood (median of `--steps` steps after
it has settled), and their ratio. The same on a 3D wall of about 1000 bricks
(saxum.structures.wall3d, 40 courses, 6 m long; saxum.flood3d), the water at mid-height
flowing at 0.5 m/s (the wall stands) normal to the wall (azimuth 90: every brick of the
upstream face exposed) and along it (azimuth 0: each course hides behind its end brick, the
shielding's worst case). Then the wall time of the four bisections of the flood bridge
example (examples/flood_bridge.py). Kernels are compiled before the clock starts.
"""

import argparse
import dataclasses
import importlib.util
import json
import platform
import time
from pathlib import Path

import numpy as np

import saxum as sx
from saxum.structures import add_grounded_running_bond_wall, wall3d

ROOT = Path(__file__).resolve().parents[1]


def _median_time(call, repeats: int) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        call()
        times.append(time.perf_counter() - start)
    return float(np.median(times))


def wall(steps: int) -> dict:
    b = sx.ModelBuilder()
    add_grounded_running_bond_wall(b, courses=40, bricks=25, brick_length=0.25,
                                   brick_height=0.065, density=1800.0)
    for pair in (("brick", "brick"), ("brick", "ground")):
        b.set_law(*pair, sx.ContactLaw(friction=0.7))
    flood = sx.FloodLoad(level=1.3, velocity=2.0)
    b.add_field_load(flood)
    model = b.finalize()
    still = sx.FloodLoad(level=1.3)
    out = np.zeros((model.body_count, 3))
    q = model.body_q0.copy()
    flood.add(model, q, 0.0, out)  # compile
    still.add(model, q, 0.0, out)
    sim = sx.Simulation(model, dt=1e-3)
    state = sim.initial_state()
    sim.run(state, 0.2)  # settle (the first steps find the contact forces from zero)
    per_step = []
    for _ in range(steps):
        start = time.perf_counter()
        sim.step(state)
        per_step.append(time.perf_counter() - start)
    load = _median_time(lambda: flood.add(model, state.body_q, 0.0, out), 200)
    hydro = _median_time(lambda: still.add(model, state.body_q, 0.0, out), 200)
    step = float(np.median(per_step))
    return {"bricks": int((model.body_kind == sx.BodyKind.FREE).sum()),
            "vertices": len(model.vertex_local), "flood_load_us": 1e6 * load,
            "still_water_us": 1e6 * hydro, "step_us": 1e6 * step,
            "load_share_of_step": load / step}


def wall_3d(steps: int) -> dict:
    model = wall3d(courses=40, length=6.0, friction=0.7)
    out = np.zeros((model.body_count, 6))
    still = sx.FloodLoad(level=1.3)
    still.add(model, model.body_q0, 0.0, out)  # compile
    result = {"bricks": int((model.body_kind == sx.BodyKind.FREE).sum()),
              "faces": len(model.face_normal_local)}
    for azimuth in (90.0, 0.0):
        flood = sx.FloodLoad(level=1.3, velocity=0.5, azimuth=azimuth)  # it stands
        flood.add(model, model.body_q0, 0.0, out)
        sim = sx.Simulation(dataclasses.replace(model, field_loads=(flood,)), dt=1e-3)
        state = sim.initial_state()
        sim.run(state, 0.05)  # settle
        per_step = []
        for _ in range(steps):
            start = time.perf_counter()
            sim.step(state)
            per_step.append(time.perf_counter() - start)
        load = _median_time(lambda f=flood, q=state.body_q: f.add(model, q, 0.0, out), 100)
        step = float(np.median(per_step))
        result[f"azimuth {azimuth:g}"] = {"flood_load_us": 1e6 * load, "step_us": 1e6 * step,
                                          "load_share_of_step": load / step}
    result["still_water_us"] = 1e6 * _median_time(
        lambda: still.add(model, state.body_q, 0.0, out), 100)
    return result


def bridge() -> dict:
    spec = importlib.util.spec_from_file_location("flood_bridge",
                                                  ROOT / "examples" / "flood_bridge.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    example.simulation(sx.FloodLoad(level=5.0, velocity=1.0)).run(
        example.simulation(sx.FloodLoad(level=5.0)).initial_state(), 0.01)  # compile
    start = time.perf_counter()
    found = example.main()
    return {"cases": {name: [r.stands, r.collapses, len(r.trials)]
                      for name, (r, _) in found.items()},
            "wall_s": time.perf_counter() - start}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=200)
    parser.add_argument("--json", type=Path)
    args = parser.parse_args()
    result = {"machine": f"{platform.processor() or platform.machine()}, "
                         f"{platform.platform()}", "wall": wall(args.steps),
              "wall_3d": wall_3d(args.steps // 4), "bridge": bridge()}
    w = result["wall"]
    print(f"wall of {w['bricks']} bricks ({w['vertices']} vertices): flood load "
          f"{w['flood_load_us']:.0f} us (still water {w['still_water_us']:.0f} us), step "
          f"{w['step_us']:.0f} us: the load is {100 * w['load_share_of_step']:.1f} % of a step")
    w = result["wall_3d"]
    print(f"3D wall of {w['bricks']} bricks ({w['faces']} faces): still water "
          f"{w['still_water_us']:.0f} us")
    for azimuth in ("90", "0"):
        a = w[f"azimuth {azimuth}"]
        print(f"  flow at azimuth {azimuth}: flood load {a['flood_load_us']:.0f} us, step "
              f"{a['step_us']:.0f} us: {100 * a['load_share_of_step']:.1f} % of a step")
    print(f"flood bridge example, four bisections: {result['bridge']['wall_s']:.1f} s")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
