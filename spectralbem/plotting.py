"""Plots of result datasets (matplotlib, headless Agg by default).

:func:`plot_dataset` picks the plot from the dataset: a sweep (curves of the scalars against the
first swept key, log axes where the values span decades, as in the seed's figures), a path
(scalars against the prescribed load or penetration), a grid state (title block; contact map
with the front coloured by the local G/Δγ, pressure and gap fields, a profile cut along the
sliding direction; for physical scenes the pressure distribution, the surface's power
spectrum and the distribution of G/Δγ along the front), a 1D state (stress and
displacement on the contact) or a grid refinement (each output's difference from the finest
grid against N, :mod:`spectralbem.refinement`). The grid state's figure is drawn by
:mod:`spectralbem.plot_maps`. A state whose status is not a verified one (``VERIFIED``, as
``spectralbem.solving.REPORTED``) is marked in red: a banner and frame on its figure, its
points crossed out on curves.
"""

from __future__ import annotations

import re

import numpy as np

from .plot_style import ROUND_OFF, VERIFIED, _banner, _suptitle, _verified, plt  # noqa: F401

SEED_CURVES = ("a_tilde", "e_tilde", "G1_over_dgamma", "G2_over_dgamma", "mu_bar")
PHYS_CURVES = ("area_fraction", "mu", "G1", "G2", "mu_adhesive", "penetration")
LABELS = {"a_tilde": "ã", "e_tilde": "ẽ", "G1_over_dgamma": "G1/Δγ", "G2_over_dgamma": "G2/Δγ",
          "mu_bar": "μ/Λ̃", "area_fraction": "area fraction", "mu": "μ", "G1": "G1 (J/m²)",
          "G2": "G2 (J/m²)", "mu_adhesive": "μ_a", "penetration": "Δ (m)",
          "mean_pressure": "p̄ (Pa)", "p_tilde": "p̃∞", "delta_tilde": "Δ̃",
          "front_length": "front length", "crack_tip_length": "crack-tip length"}

__all__ = ["plot_dataset", "plot_contact", "plot_path", "plot_sweep", "plot_profile_1d",
           "plot_refinement"]


def _kind(ds) -> str:
    if "refinement_sizes" in ds.attrs:
        return "refinement"
    if "sweep_keys" in ds.attrs:
        return "sweep"
    if "step" in ds.dims:
        return "path"
    if "y" in ds.dims:
        return "grid"
    return "oned"


def plot_dataset(ds, path=None):
    """The natural plot of any result dataset; returns the figure (PNG written to ``path``)."""
    fig = {"sweep": plot_sweep, "path": plot_path, "grid": plot_contact,
           "oned": plot_profile_1d, "refinement": plot_refinement}[_kind(ds)](ds)
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig




def _zero_friction(da) -> bool:
    """A friction variable that is zero to round-off everywhere (no panel of noise)."""
    v = np.asarray(da.values, float)
    v = v[np.isfinite(v)]
    return da.name.startswith("mu") and (v.size == 0 or np.abs(v).max() < ROUND_OFF)


def _num(v) -> str:
    """A value to 6 significant digits, an exponent without "+" or leading zeros (1e-5)."""
    text = f"{float(v):.6g}"
    if "e" in text:
        mant, exp = text.split("e")
        text = f"{mant}e{int(exp)}"
    return text


def _with_unit(text: str, unit) -> str:
    """``text`` followed by its unit (none for dimensionless quantities)."""
    return f"{text} {unit}" if unit not in ("1", "", None) else text


def _bare(label: str) -> str:
    """A label without its trailing unit in parentheses ("Δ (m)" → "Δ")."""
    return re.sub(r" \([^()]*\)$", "", label)


def _control_symbol(ds) -> tuple[str, str]:
    """The prescribed control's symbol and unit ("p̄", "Pa")."""
    cv = ds["control_value"]
    name = cv.attrs.get("long_name", "control").replace("prescribed ", "")
    return _bare(LABELS.get(name, name)), cv.attrs.get("units", "1")


def _curve_names(ds) -> list[str]:
    return [n for n in (SEED_CURVES if "a_tilde" in ds else PHYS_CURVES)
            if n in ds and not _zero_friction(ds[n])]


def _curves(ds, xname, xlabel, title, x=None, fig=None):
    """Curves of the scalars against ``xname`` (drawn into ``fig``, a figure or subfigure,
    when given)."""
    names = _curve_names(ds)
    n = len(names)
    cols = min(3, n)
    rows = int(np.ceil(n / cols))
    if fig is None:
        fig = plt.figure(figsize=(4.3 * cols, 3.4 * rows), constrained_layout=True)
    axes = fig.subplots(rows, cols, squeeze=False)
    x = np.asarray(ds[xname].values if x is None else x, float)
    logx = np.all(x > 0) and x.max() / x.min() > 20
    other = [d for d in ds[names[0]].dims if d != xname]
    bad = None
    if "status" in ds and set(ds["status"].dims) == {xname, *other}:
        st = ds["status"].transpose(xname, *other).values.astype(str).reshape(len(x), -1)
        bad = ~np.isin(st, VERIFIED)
    for ax, name in zip(axes.flat, names, strict=False):
        da = ds[name]
        if other:
            da = da.transpose(xname, *other)
        y = np.asarray(da.values, float).reshape(len(x), -1)
        labels = ([_with_unit(f"{other[0]} = {_num(v)}", ds[other[0]].attrs.get("units"))
                   for v in np.asarray(ds[other[0]].values, float)]
                  if len(other) == 1 and other[0] in ds.coords else [None] * y.shape[1])
        for j in range(y.shape[1]):
            ax.plot(x, y[:, j], "o-", ms=3, label=labels[j])
            if bad is not None and bad[:, j].any():  # values of states not verified
                ax.plot(x[bad[:, j]], y[bad[:, j], j], "x", ms=8, color="C3",
                        label=NOT_VERIFIED if j == 0 else None)
        if ax is axes.flat[0] and (labels[0] is not None or (bad is not None
                                                             and bad.any())):
            ax.legend(fontsize=8)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(LABELS.get(name, name))
        if logx:
            ax.set_xscale("log")
        yy = y[np.isfinite(y)]
        if name.startswith("G") and name.endswith("dgamma") and yy.size and np.all(yy > 0):
            ax.set_yscale("log")
        ax.grid(alpha=0.3)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    if bad is not None and bad.any():
        fig.suptitle(f"{title}\n{int(bad.sum())} of {bad.size} states NOT VERIFIED "
                     "(red ×: values unverified)", color="C3")
    else:
        fig.suptitle(title)
    return fig


def plot_sweep(ds):
    """Curves of the scalars against the first swept key (one line per other swept value)."""
    import json

    keys = json.loads(ds.attrs["sweep_keys"])
    # drawn in the order of the swept values (a sweep keeps the order given: 10, 0.1, 1)
    ds = ds.sortby([d for d in ds.dims if d != "step" and d in ds.coords])
    dim = list(ds[list(ds.data_vars)[0]].dims)[0]
    unit = ds[dim].attrs.get("units", "1")
    label = f"{keys[0]}" + (f" ({unit})" if unit not in ("1", "") else "")
    return _curves(ds, dim, label, f"sweep over {', '.join(keys)}")


NOT_VERIFIED = "not converged (unverified)"

#: at most this many steps of a path get a contact map under its curves
PATH_MAPS = 6


def plot_refinement(ds):
    """A grid refinement (spectralbem.refinement): each moving quantity against N as its
    relative difference from the finest grid (%), one curve per load step, Richardson's
    N → ∞ estimate dashed where the changes are asymptotic; hollow markers: states not
    verified (left out of the estimates)."""
    from .refinement import VERIFIED, _control, varying

    names = varying(ds)
    cols = max(1, min(3, len(names)))
    rows = max(1, int(np.ceil(len(names) / cols)))
    fig, axes = plt.subplots(rows, cols, figsize=(4.3 * cols, 3.4 * rows), squeeze=False,
                             constrained_layout=True)
    n = np.asarray(ds["N"].values, float)
    steps = range(ds.sizes["step"]) if "step" in ds.dims else [None]
    symbol, unit = _control_symbol(ds) if "control_value" in ds else ("step", "1")

    def load(k):  # the legend's name of step k: its control value with its unit
        if "control_value" not in ds:
            return f"step {k}"
        return _with_unit(f"{symbol} = {_num(ds['control_value'].values[k])}", unit)

    for ax, q in zip(axes.ravel(), names, strict=False):
        for k in steps:
            sel = ds if k is None else ds.isel(step=k)
            ok = np.isin(np.asarray(sel["status"].values).astype(str), VERIFIED)
            v = np.asarray(sel[q].values, float)
            ref = abs(v[-1]) if np.isfinite(v[-1]) and v[-1] != 0 else np.nan
            rel = 100 * (v - v[-1]) / ref
            line, = ax.plot(n, rel, "-", label=None if k is None else load(k))
            ax.plot(n[ok], rel[ok], "o", color=line.get_color())
            ax.plot(n[~ok], rel[~ok], "o", mfc="none", color=line.get_color())
            lim = float(sel[f"{q}_limit"].values)
            if np.isfinite(lim):
                ax.axhline(100 * (lim - v[-1]) / ref, ls="--", lw=0.8, color=line.get_color())
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.set_xscale("log", base=2)
        ax.set_xticks(n, [str(int(x)) for x in n])
        ax.set_xlabel("N")
        ax.set_ylabel(f"{_bare(LABELS.get(q, q))}: % difference from N = {int(n[-1])}")
    for ax in axes.ravel()[len(names):]:
        ax.set_visible(False)
    if len(steps) > 1 and names:
        axes[0, 0].legend(fontsize=7)
    name = ds.attrs.get("title", "spectralbem").replace("spectralbem result: ", "")
    ctrl = _control(ds)
    if steps == [None] and ctrl in ds:  # one load, named here as it has no legend
        name += " at " + _with_unit(f"{_bare(LABELS.get(ctrl, ctrl))} = "
                                    f"{_num(ds[ctrl].values.flat[-1])}",
                                    ds[ctrl].attrs.get("units"))
    fig.suptitle(f"{name}: grid refinement (dashed: Richardson's N → ∞ estimate; hollow: "
                 "states not verified)", fontsize=10)
    return fig


def plot_path(ds):
    """Scalars along a load/unload path against the prescribed control value (arrows: step
    order) and, under them, the contact map of each step (evenly chosen when there are more
    than ``PATH_MAPS``) with its front coloured by G/Δγ where adhesive."""
    name = ds["control_value"].attrs.get("long_name", "control").replace("prescribed ", "")
    unit = ds["control_value"].attrs.get("units", "1")
    label = LABELS.get(name, name) + (f" ({unit})" if unit not in ("1", "")
                                      and "(" not in LABELS.get(name, "") else "")
    maps = "contact" in ds and "x" in ds.dims and "y" in ds.dims
    cols = min(3, len(_curve_names(ds)))
    rows = int(np.ceil(len(_curve_names(ds)) / cols))
    fig = plt.figure(figsize=(4.3 * max(cols, 2), 3.4 * rows + (3.3 if maps else 0.0)),
                     constrained_layout=True)
    top, bottom = (fig.subfigures(2, 1, height_ratios=[3.4 * rows, 3.3]) if maps
                   else (fig, None))
    _curves(ds, "step", label, "load path (arrows: step order)",
            x=ds["control_value"].values, fig=top)
    for ax in top.axes:
        for line in ax.get_lines():
            xd, yd = line.get_xdata(), line.get_ydata()
            for i in range(len(xd) - 1):
                if np.all(np.isfinite([xd[i], xd[i + 1], yd[i], yd[i + 1]])):
                    ax.annotate("", (xd[i + 1], yd[i + 1]), (xd[i], yd[i]),
                                arrowprops=dict(arrowstyle="->", color=line.get_color()))
    if maps:
        _step_maps(bottom, ds, label)
    return fig


def _step_maps(fig, ds, label):
    """A row of contact maps, one per chosen step (title: step, control value, area,
    status; red when not verified), with axis ticks as on the single state's map."""
    from matplotlib.ticker import MaxNLocator

    n = ds.sizes["step"]
    steps = np.unique(np.linspace(0, n - 1, min(n, PATH_MAPS)).round().astype(int))
    axes = fig.subplots(1, len(steps), squeeze=False)[0]
    seed = "pressure_tilde" in ds
    scale, unit = (1.0, "k⁻¹") if seed else (1e3, "mm")
    symbol, cunit = _control_symbol(ds)
    x, y = ds["x"].values * scale, ds["y"].values * scale
    ext = (x[0], x[-1], y[0], y[-1])
    X, Y = np.meshgrid(x, y, indexing="ij")
    sc = None
    for ax, k in zip(axes, steps, strict=True):
        st = ds.isel(step=int(k))
        ax.imshow(st["contact"].values.astype(bool).T, origin="lower", extent=ext,
                  cmap="Greys", vmin=0, vmax=1.6, aspect="equal")
        if "G_front" in st:
            G = st["G_front"].values
            ok = np.isfinite(G)
            if ok.any():
                sc = ax.scatter(X[ok], Y[ok], c=np.clip(G[ok], 0.0, 2.0), s=1.5,
                                marker="s", cmap="coolwarm", vmin=0.0, vmax=2.0)
        frac = (f", area {float(st['area_fraction']):.3f}" if "area_fraction" in st else "")
        status = st["status"].item() if "status" in st else "partial"
        load = _with_unit(f"{symbol} = {_num(st['control_value'])}", cunit)
        ax.set_title(f"step {int(k)}: {load}{frac}\n"
                     + (status if _verified(status) else _banner(status)), fontsize=8,
                     color="k" if _verified(status) else "C3")
        for axis in (ax.xaxis, ax.yaxis):  # a scale as on the single state's map
            axis.set_major_locator(MaxNLocator(3))
        ax.tick_params(labelsize=7)
        ax.set_xlabel(f"x ({unit})", fontsize=7)
        if ax is axes[0]:
            ax.set_ylabel(f"y ({unit})", fontsize=7)
        else:
            ax.tick_params(labelleft=False)
    if sc is not None:
        fig.colorbar(sc, ax=list(axes), label="G/Δγ on the front", shrink=0.8)
    fig.suptitle(f"contact of each step (x to the right; control: {label})", fontsize=9)


def plot_contact(ds, path=None):
    """Grid state: a title block (scene, material, v and its angle to x, p̄, μ, area,
    status; a red banner and frame when the state is not verified); the contact map with
    the front coloured by G/Δγ when adhesive and an arrow along the sliding direction; the
    pressure (diverging around p = 0 with ticks on both sides, non-contact masked, the scale
    clipped to the 1st-99th percentile with extend arrows and the clipped extremes named);
    the gap (log scale); a profile cut through the highest pressure along the sliding
    direction (x at rest and for the seed's sinusoid; its axis names the direction), drawn
    on the maps and zoomed to the contact; for physical scenes, a second row (pressure
    distribution, power spectrum, G/Δγ along the front). Drawn by
    :mod:`spectralbem.plot_maps`."""
    from .plot_maps import plot_contact as draw

    return draw(ds, path)


def plot_profile_1d(ds, path=None):
    """1D state (seed method): pressure p/p* = −σ/p* (compressive positive, as the 2D maps)
    and displacement u/Λ on the contact; the indenter slides along +x (−x in a physical scene
    whose velocity points there: its fields are mirrored)."""
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    x = ds["x_tilde"].values
    along = "−x" if float(ds.attrs.get("velocity_x", 1.0)) < 0 else "+x"
    axes[0].plot(x, -ds["sigma_tilde"].values, "C3-")
    axes[0].axhline(0.0, color="0.5", lw=0.8)
    axes[0].set_xlabel(f"k x (sliding along {along})")
    axes[0].set_ylabel("p/p* (compressive +)")
    status = ds["status"].item()
    axes[0].set_title(f"{ds.attrs.get('model', '')}: status {status}, "
                      f"ã = {float(ds['a_tilde']):.4g}")
    if not _verified(status):
        _suptitle(fig, "", status, fontsize=10)
    axes[1].plot(x, ds["u_tilde"].values, "C0-")
    axes[1].set_xlabel(f"k x (sliding along {along})")
    axes[1].set_ylabel("u/Λ")
    axes[1].set_title(f"ẽ = {float(ds['e_tilde']):.4g}, μ̄ = {float(ds['mu_bar']):.4g}")
    for ax in axes:
        ax.grid(alpha=0.3)
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
