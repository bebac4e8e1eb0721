"""Pictures of an ensemble (saxum.ensemble): IDA curves and the fragility curve, with
matplotlib.figure.Figure (never pyplot)."""

from __future__ import annotations

from os import PathLike

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import NullFormatter, ScalarFormatter

from .ensemble import Ensemble
from .errors import InputError

__all__ = ["plot_ensemble"]

_LABELS = {"peak_displacement": "peak displacement [m]",
           "peak_horizontal": "peak horizontal displacement [m]", "peak_drift": "peak drift [-]",
           "peak_rotation": "peak rotation [rad]",
           "residual_displacement": "displacement at the end [m]"}


def plot_ensemble(ensemble: Ensemble, path: str | PathLike | None = None, *,
                  edp: str = "peak_drift", threshold: float | None = None,
                  level: float = 0.95, title: str = "",
                  figsize: tuple[float, float] = (11.0, 4.5), dpi: int = 150) -> Figure:
    """Left: each record's demand `edp` against the scale (its IDA curve; a collapse is a
    cross, drawn at the right edge). Right: the fraction of runs that failed (collapsed, or
    `edp` above `threshold`) per scale (MSA) or the records' capacities as an empirical
    distribution (IDA), with the fitted lognormal fragility and its confidence band at
    `level` (saxum.fragility)."""
    if edp not in _LABELS:
        raise InputError(f"no demand {edp!r}; the demands: {', '.join(_LABELS)}")
    runs = ensemble.runs
    if not np.any(runs["collapsed"] >= 0):
        raise InputError(f"{ensemble.path}: no run has finished yet")
    measure = "PGA [g]" if ensemble.spec.measure == "pga" else "scale factor [-]"
    fig = Figure(figsize=figsize, layout="constrained")
    ida, frag = fig.subplots(1, 2)
    ok = runs["collapsed"] == 0
    top = float(np.nanmax(np.where(ok, runs[edp], np.nan), initial=0.0)) or 1.0
    for k, name in enumerate(ensemble.record_names):
        mine = runs["record"] == k
        order = np.argsort(runs["scale"][mine])
        scale = runs["scale"][mine][order]
        standing = (runs["collapsed"][mine] == 0)[order]
        down = (runs["collapsed"][mine] == 1)[order]
        if not mine.any():
            continue
        line = ida.plot(runs[edp][mine][order][standing], scale[standing], ".-", lw=0.8,
                        ms=3, label=name if len(ensemble.record_names) <= 12 else None)
        if down.any():
            ida.plot(np.full(down.sum(), 1.1 * top), scale[down], "x",
                     color=line[0].get_color(), ms=4)
    ida.axvline(1.1 * top, color="#c0152f", lw=0.8, ls=":")
    ida.text(1.1 * top, 1.0, "collapse ", color="#c0152f", fontsize=8, rotation=90,
             va="top", ha="right", transform=ida.get_xaxis_transform())
    ida.set_xlabel(_LABELS[edp])
    ida.set_ylabel(measure)
    ida.set_title("IDA curves" if ensemble.spec.ida else "stripes", fontsize=10)
    ida.grid(alpha=0.3)
    if ida.get_legend_handles_labels()[0]:
        ida.legend(fontsize=6, loc="lower right")
    failed = ensemble.failed(None if threshold is None else edp, threshold)
    what = "collapse" if threshold is None else f"{edp} > {threshold:g} or collapse"
    try:
        fit = ensemble.fragility(None if threshold is None else edp, threshold)
    except InputError as err:  # (the runs are drawn all the same)
        fit, why = None, str(err).removeprefix("fragility: ")
    x = np.geomspace(min(ensemble.spec.scales) / 2, 2 * max(ensemble.spec.scales), 200)
    if ensemble.spec.ida:
        stands, fails = ensemble.capacities(failed)
        read = np.array([not e for e in ensemble.record_errors])
        cap = np.sort((0.5 * (stands + fails))[np.isfinite(fails) & read])
        frag.step(np.concatenate(([x[0]], cap, [x[-1]])),
                  np.arange(cap.size + 2).clip(max=cap.size) / read.sum(), where="post",
                  color="k", lw=1.0, label=f"capacities of {cap.size} of {read.sum()} records")
    else:
        ran = runs["collapsed"] >= 0
        scales = np.unique(runs["scale"][ran])
        share = [failed[ran & (runs["scale"] == s)].mean() for s in scales]
        frag.plot(scales, share, "o", color="k", ms=4, label="fraction of runs failed")
    if fit is not None:
        lo, hi = fit.band(x, level)
        frag.fill_between(x, lo, hi, color="#1f5fa8", alpha=0.2,
                          label=f"{100 * level:g} % band (Fisher information)")
        frag.plot(x, fit.probability(x), color="#1f5fa8",
                  label=f"lognormal: theta {fit.theta:.3g}, beta {fit.beta:.3g}")
    frag.set_xscale("log")
    frag.xaxis.set_major_formatter(ScalarFormatter())
    frag.xaxis.set_minor_formatter(NullFormatter())
    stripes = list(ensemble.spec.scales)
    frag.set_xticks(stripes if len(stripes) <= 10 else stripes[:: -(-len(stripes) // 10)])
    frag.set_xlim(x[0], x[-1])
    frag.set_xlabel(measure)
    frag.set_ylabel(f"P({what})")
    frag.set_ylim(0.0, 1.0)
    frag.set_title("fragility (Baker 2015, maximum likelihood)" if fit is not None
                   else f"no fragility fit: {why}", fontsize=10 if fit is not None else 7,
                   wrap=True)
    frag.grid(alpha=0.3)
    frag.legend(fontsize=7, loc="upper left")
    if title:
        fig.suptitle(title, fontsize=11)
    if path is not None:
        fig.savefig(path, dpi=dpi)
    return fig
