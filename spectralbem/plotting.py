"""Plots of result datasets (matplotlib, headless Agg by default)."""

from __future__ import annotations

import os

import matplotlib

if not os.environ.get("MPLBACKEND"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def plot_contact(ds, path=None):
    """Contact map, pressure field and a profile cut along x through the highest pressure.

    Returns the figure; writes a PNG when ``path`` is given.
    """
    x = ds["x"].values * 1e3
    y = ds["y"].values * 1e3
    p = ds["pressure"].values
    fig, axes = plt.subplots(1, 3, figsize=(13, 4), constrained_layout=True)
    ext = (x[0], x[-1], y[0], y[-1])
    ax = axes[0]
    ax.imshow(ds["contact"].values.T, origin="lower", extent=ext, cmap="Greys", aspect="auto")
    ax.set_title(f"contact (area fraction {float(ds['area_fraction']):.3f})")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax = axes[1]
    im = ax.imshow(p.T / 1e3, origin="lower", extent=ext, cmap="magma", aspect="auto")
    fig.colorbar(im, ax=ax, label="pressure (kPa)")
    ax.set_title(f"pressure, μ = {float(ds['mu']):.4f}")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax = axes[2]
    j = int(np.unravel_index(np.argmax(p), p.shape)[1])
    h = ds["heights"].values[:, j]
    w = h - ds["heights"].values.max() + float(ds["penetration"])
    top, slab = -w * 1e6, -ds["displacement"].values[:, j] * 1e6
    hi, lo = top.max() + 0.1 * np.ptp(top), slab.min() - 0.1 * np.ptp(top)
    ax.fill_between(x, top, hi, color="0.75", label="rigid indenter")
    ax.fill_between(x, lo, slab, color="C0", alpha=0.35, label="slab")
    ax.plot(x, slab, "C0-", lw=1)
    ax.set_ylim(lo, hi)
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("height (μm)")
    ax.set_title(f"profile cut at y = {y[j]:.3g} mm")
    ax.legend(loc="best")
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
