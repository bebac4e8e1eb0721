"""Pictures of a 2D model's state with matplotlib (headless backend)."""

from collections.abc import Sequence

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

from .model import BodyKind, Model  # noqa: E402

__all__ = ["draw_state", "save_states"]


def draw_state(ax, model: Model, q: np.ndarray, *, title: str = "", vmax: float | None = None):
    """Draw the blocks at coordinates q [m, rad] coloured by displacement from the initial
    position [m], the initial outline dashed; returns the PolyCollection (for a colour bar)."""
    n = model.body_count
    initial = [model.vertices(b) for b in range(n)]
    now = [model.vertices(b, q) for b in range(n)]
    moved = np.hypot(*(q[:, :2] - model.body_q0[:, :2]).T)
    mobile = model.body_kind == BodyKind.FREE
    ax.add_collection(PolyCollection([initial[b] for b in range(n) if mobile[b]],
                                     facecolors="none", edgecolors="0.6", linestyles="--",
                                     linewidths=0.6))
    ax.add_collection(PolyCollection([now[b] for b in range(n) if not mobile[b]],
                                     facecolors="0.75", edgecolors="0.3", hatch="//",
                                     linewidths=0.6))
    blocks = PolyCollection([now[b] for b in range(n) if mobile[b]], cmap="viridis",
                            edgecolors="k", linewidths=0.6)
    blocks.set_array(moved[mobile])
    blocks.set_clim(0.0, vmax if vmax is not None else max(float(moved[mobile].max()), 1e-12))
    ax.add_collection(blocks)
    pts = np.concatenate(initial + now)
    pad = 0.05 * np.ptp(pts, axis=0).max()
    ax.set_xlim(pts[:, 0].min() - pad, pts[:, 0].max() + pad)
    ax.set_ylim(pts[:, 1].min() - pad, pts[:, 1].max() + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if title:
        ax.set_title(title, fontsize=10)
    return blocks


def save_states(path: str, panels: Sequence[tuple[Model, np.ndarray, str]]) -> None:
    """Write a PNG with one panel per (model, q, title), each with a displacement colour bar."""
    fig, axes = plt.subplots(1, len(panels), figsize=(6 * len(panels), 4.5), squeeze=False)
    for ax, (model, q, title) in zip(axes[0], panels, strict=True):
        blocks = draw_state(ax, model, q, title=title)
        fig.colorbar(blocks, ax=ax, shrink=0.6, label="displacement [m]")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
