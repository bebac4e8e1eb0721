"""A tiny ensemble for the tests: a rocking block 0.2 x 1 m, two short records (one-sine
pulses of 0.6 s, as CSV files) at scales 1, 2, 3: 6 runs."""

import numpy as np

SCENARIO = """
[structure]
type = "pier"
width = 0.2
height = 1.0
[[laws]]
groups = ["*", "*"]
friction = 2.0
kind = "signorini_coulomb"
[solver]
dt = 2e-3
[output]
duration = 1.0
interval = 0.02
[ensemble]
records = "records"
scales = "1:3:1"
after = 0.5
"""


def write_records(folder, count: int = 2) -> list:
    """`count` CSV records in `folder`: one-sine pulses of 0.6 s, 0.3 g x (1 + k / 4)."""
    folder.mkdir(exist_ok=True)
    t = np.arange(0.0, 0.6001, 0.01)
    paths = []
    for k in range(count):
        path = folder / f"pulse{k}.csv"
        a = 0.3 * (1 + k / 4) * np.sin(2 * np.pi * t / 0.6)
        path.write_text("# units: g\n" + "".join(f"{x:.2f},{y:.6f}\n" for x, y in zip(
            t, a, strict=True)))
        paths.append(path)
    return paths


def write_scenario(folder) -> object:
    path = folder / "block.toml"
    path.write_text(SCENARIO)
    write_records(folder / "records")
    return path
