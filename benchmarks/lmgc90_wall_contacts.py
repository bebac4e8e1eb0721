"""Benchmark: contacts an LMGC90-style settling wall finds with saxum's default alert, with
the alert from the blocks of each pair (detection.per_pair), and with an alert as large as
LMGC90's example uses.

The wall: the shape of LMGC90's RIGID_2D/WallPL_GroundJC example (bricks 0.05 m high on a
ground in two parts, one of which settles): 10 courses of 8 bricks 0.2 x 0.05 m, running
bond, mu = 0.6 (IQS_CLB), the right half of the ground going down 2 cm in 0.2 s, run 0.3 s
at dt = 1e-3 s. LMGC90's alert for it is at least one brick's height: its shipped
Vloc_Rloc.INI lists open contacts (noctc, zero impulse) with gapTT = 0.05 m, a brick of the
second course with the ground under the first (contacts 1, 2, 7, 8 of that file). Per
setting: the alert [m], contacts found (at the start, most in a step, at the end), those
carrying load (R_n > 0) at the end, the bricks settled more than 1 cm, and the wall time per
step [ms] (one run; the machine is shared, so compare within one run only).

    PYTHONPATH=src python benchmarks/lmgc90_wall_contacts.py
"""

import time

import numpy as np

from saxum.scenario import parse_scenario

WALL = """
[output]
duration = 0.3
[detection]
per_pair = {per_pair}
[[loads.settlements]]
block = "ground 2"
time = 0.2
magnitude = 0.02
[structure]
ground_splits = [0.5]
brick_length = 0.2
type = "wall"
brick_height = 0.05
bricks = 8
courses = 10
[[laws]]
kind = "signorini_coulomb"
groups = ["*", "*"]
friction = 0.6
{alert}
[[laws]]
kind = "none"
groups = ["ground", "ground"]
"""


def _run(alert: float | None, per_pair: bool) -> dict:
    text = WALL.format(alert="" if alert is None else f"alert = {alert}",
                       per_pair=str(per_pair).lower())
    sim = parse_scenario(text).build_simulation()
    m = sim.model
    state = sim.initial_state()
    start = sim.detector.contacts_at(state.body_q).count
    steps = round(0.3 / sim.integrator.dt)
    t0 = time.perf_counter()
    for _ in range(steps):
        sim.step(state)
    wall = (time.perf_counter() - t0) / steps
    c = state.contacts
    loaded = int((c.impulse[:c.count, 1] > 0.0).sum())
    free = m.body_kind == 0
    settled = int((m.body_q0[free, 1] - state.body_q[free, 1] > 0.01).sum())
    law = m.laws[m.group_law[m.group_names.index("brick"), m.group_names.index("brick")]]
    if law.alert is not None:
        used = f"{law.alert:g} (the law's)"
    elif per_pair:
        pair = sim.detector._body_alert[free]
        used = f"{pair.min():.4f}..{pair.max():.4f} (per pair)"
    else:
        used = f"{sim.detector.alert:.4f} (model-wide)"
    return {"alert [m]": used, "contacts at start": start,
            "most in a step": int(np.max(sim.log.contacts)), "at the end": c.count,
            "loaded at the end": loaded, "settled > 1 cm": f"{settled} of {int(free.sum())}",
            "ms/step": f"{1e3 * wall:.2f}"}


def main() -> None:
    settings = {"saxum's default": (None, False), "per pair": (None, True),
                "LMGC90's (one brick height)": (0.05, False)}
    for name, (alert, per_pair) in settings.items():
        row = _run(alert, per_pair)
        print(f"{name}: " + ", ".join(f"{k} {v}" for k, v in row.items()))


if __name__ == "__main__":
    main()
