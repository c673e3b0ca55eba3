"""Plots of result datasets (matplotlib, headless Agg by default).

:func:`plot_dataset` picks the plot from the dataset: a sweep (curves of the scalars against the
first swept key, log axes where the values span decades, as in the seed's figures), a path
(scalars against the prescribed load or penetration), a grid state (title block; contact map
with the front coloured by the local G/Δγ, pressure and gap fields, a profile cut along the
sliding direction; for physical scenes the pressure distribution, the surface's power
spectrum and the distribution of G/Δγ along the front), a 1D state (stress and
displacement on the contact) or a grid refinement (each output's difference from the finest
grid against N, :mod:`spectralbem.refinement`).
"""

from __future__ import annotations

import os

import matplotlib

if not os.environ.get("MPLBACKEND"):
    matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from .bands import front_cells  # noqa: E402

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


#: a friction coefficient below this is zero to round-off (an elastic or resting scene)
ROUND_OFF = 1e-12


def _zero_friction(da) -> bool:
    """A friction variable that is zero to round-off everywhere (no panel of noise)."""
    v = np.asarray(da.values, float)
    v = v[np.isfinite(v)]
    return da.name.startswith("mu") and (v.size == 0 or np.abs(v).max() < ROUND_OFF)


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
        labels = ([f"{other[0]} = {v:g}" for v in np.asarray(ds[other[0]].values, float)]
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
    fig.suptitle(title)
    return fig


def plot_sweep(ds):
    """Curves of the scalars against the first swept key (one line per other swept value)."""
    import json

    keys = json.loads(ds.attrs["sweep_keys"])
    dim = list(ds[list(ds.data_vars)[0]].dims)[0]
    unit = ds[dim].attrs.get("units", "1")
    label = f"{keys[0]}" + (f" ({unit})" if unit not in ("1", "") else "")
    return _curves(ds, dim, label, f"sweep over {', '.join(keys)}")


#: statuses of verified states; points of the others are crossed out in red
VERIFIED = ("partial", "full_contact", "detached")
NOT_VERIFIED = "not converged (unverified)"

#: at most this many steps of a path get a contact map under its curves
PATH_MAPS = 6


def plot_refinement(ds):
    """A grid refinement (spectralbem.refinement): each moving quantity against N as its
    relative difference from the finest grid (%), one curve per load step, Richardson's
    N → ∞ estimate dashed where the changes are asymptotic; hollow markers: states not
    verified (left out of the estimates)."""
    from .refinement import VERIFIED, varying

    names = varying(ds)
    cols = max(1, min(3, len(names)))
    rows = max(1, int(np.ceil(len(names) / cols)))
    fig, axes = plt.subplots(rows, cols, figsize=(4.3 * cols, 3.4 * rows), squeeze=False,
                             constrained_layout=True)
    n = np.asarray(ds["N"].values, float)
    steps = range(ds.sizes["step"]) if "step" in ds.dims else [None]
    for ax, q in zip(axes.ravel(), names, strict=False):
        for k in steps:
            sel = ds if k is None else ds.isel(step=k)
            ok = np.isin(np.asarray(sel["status"].values).astype(str), VERIFIED)
            v = np.asarray(sel[q].values, float)
            ref = abs(v[-1]) if np.isfinite(v[-1]) and v[-1] != 0 else np.nan
            rel = 100 * (v - v[-1]) / ref
            line, = ax.plot(n, rel, "-", label=None if k is None else f"step {k}")
            ax.plot(n[ok], rel[ok], "o", color=line.get_color())
            ax.plot(n[~ok], rel[~ok], "o", mfc="none", color=line.get_color())
            lim = float(sel[f"{q}_limit"].values)
            if np.isfinite(lim):
                ax.axhline(100 * (lim - v[-1]) / ref, ls="--", lw=0.8, color=line.get_color())
        ax.axhline(0.0, color="0.6", lw=0.5)
        ax.set_xscale("log", base=2)
        ax.set_xticks(n, [str(int(x)) for x in n])
        ax.set_xlabel("N")
        ax.set_ylabel(f"{LABELS.get(q, q)}: % from N = {int(n[-1])}")
    for ax in axes.ravel()[len(names):]:
        ax.set_visible(False)
    if len(steps) > 1 and names:
        axes[0, 0].legend(fontsize=7)
    fig.suptitle(f"{ds.attrs.get('title', 'spectralbem')}: grid refinement (dashed: "
                 "Richardson's N → ∞ estimate)", fontsize=10)
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
    """A row of contact maps, one per chosen step (title: step, control value, area)."""
    n = ds.sizes["step"]
    steps = np.unique(np.linspace(0, n - 1, min(n, PATH_MAPS)).round().astype(int))
    axes = fig.subplots(1, len(steps), squeeze=False)[0]
    seed = "pressure_tilde" in ds
    scale = 1.0 if seed else 1e3
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
        status = f"\n{st['status'].item()}" if "status" in st else ""
        ax.set_title(f"step {int(k)}: {float(st['control_value']):.4g}{frac}{status}",
                     fontsize=8)
        ax.set_xticks([])
        ax.set_yticks([])
    if sc is not None:
        fig.colorbar(sc, ax=list(axes), label="G/Δγ on the front", shrink=0.8)
    fig.suptitle(f"contact of each step (x to the right; control: {label})", fontsize=9)


def _cut_along(field_, i0, j0, vx, vy):
    """Nearest-cell samples of a periodic field along the line through (i0, j0) in the
    direction (vx, vy) measured in cells (one period of the longer axis)."""
    nx, ny = field_.shape
    n = max(nx, ny)
    s = np.arange(n) - n // 2
    norm = max(abs(vx), abs(vy))
    ii = (i0 + np.rint(s * vx / norm).astype(int)) % nx
    jj = (j0 + np.rint(s * vy / norm).astype(int)) % ny
    return s, ii, jj


def _title_block(ds, seed: bool) -> str:
    """Scene, material, sliding velocity, load, μ and contact area in one line each."""
    import json

    try:
        spec = json.loads(ds.attrs.get("scene", "{}"))
    except ValueError:
        spec = {}
    name = ds.attrs.get("title", "").replace("spectralbem result: ", "") or "state"
    mu = float(ds["mu_bar"] if seed else ds["mu"])
    mu_text = f"{mu:.4g}" if abs(mu) >= ROUND_OFF else "0"
    area = float(ds["area_fraction"]) if "area_fraction" in ds else float(
        ds["contact"].values.mean())
    if seed:
        a = ds.attrs
        return (f"{name}: ζ = {a.get('zeta', float('nan')):g}, β = "
                f"{a.get('beta', float('nan')):g}, Γ = {a.get('Gamma', float('nan')):g}, "
                f"p̃ = {float(ds['p_tilde']):.4g}, μ/Λ̃ = {mu_text}, "
                f"ã = {float(ds['a_tilde']):.4g}, status {ds['status'].item()}")
    mat = spec.get("material", {})
    mtext = ", ".join(f"{k} {v:g}" for k, v in mat.items()
                      if k != "kind" and isinstance(v, (int, float)))
    v = float(np.hypot(ds.attrs.get("velocity_x", 0.0), ds.attrs.get("velocity_y", 0.0)))
    return (f"{name} — {mat.get('kind', '')} ({mtext}); v = {v:.3g} m/s; "
            f"p̄ = {float(ds['mean_pressure']):.4g} Pa; μ = {mu_text}; "
            f"contact area {area:.4f}; {ds['status'].item()}")


def _cut(ds, p, x, y):
    """The profile cut through the highest pressure along the sliding direction (x if at
    rest): (distance along it, row and column indices, unit vector in the (x, y) plane)."""
    vx, vy = ds.attrs.get("velocity_x", 0.0), ds.attrs.get("velocity_y", 0.0)
    if vx == 0 and vy == 0:
        vx = 1.0
    hx, hy = x[1] - x[0], (y[1] - y[0]) if len(y) > 1 else 1.0
    i0, j0 = np.unravel_index(np.argmax(p), p.shape)
    s, ii, jj = _cut_along(p, i0, j0, vx / hx, vy / hy)
    norm = max(abs(vx / hx), abs(vy / hy))
    return s * np.hypot(vx / norm, vy / norm), ii, jj, np.array([vx, vy]) / np.hypot(vx, vy)


def _draw_cut(ax, x, y, ii, jj):
    """The cut's cells as a dashed line on a map (broken where it wraps around the cell)."""
    xs, ys = x[ii], y[jj]
    jump = np.flatnonzero((np.abs(np.diff(xs)) > 0.5 * np.ptp(x))
                          | (np.abs(np.diff(ys)) > 0.5 * max(np.ptp(y), 1e-300))) + 1
    for seg in np.split(np.arange(xs.size), jump):
        ax.plot(xs[seg], ys[seg], "--", color="C2", lw=0.9)


def plot_contact(ds, path=None):
    """Grid state: a title block (scene, material, v, p̄, μ, area, status); the contact map
    with the front coloured by G/Δγ when adhesive and the sliding direction; the pressure
    (diverging around p = 0, non-contact masked); the gap (log scale); a profile cut through
    the highest pressure along the sliding direction, drawn on the maps and zoomed to the
    contact."""
    from matplotlib import colors

    seed = "pressure_tilde" in ds
    scale, unit = (1.0, "k⁻¹") if seed else (1e3, "mm")
    x = ds["x"].values * scale
    y = ds["y"].values * scale
    p = ds["pressure_tilde"].values if seed else ds["pressure"].values
    pl, pu = ("p/p*", 1.0) if seed else ("pressure (kPa)", 1e-3)
    contact = ds["contact"].values.astype(bool)
    ext = (x[0], x[-1], y[0], y[-1])
    panels = 3 if seed or "gap" not in ds else 4
    extra = not seed and "heights" in ds
    fig = plt.figure(figsize=(4.4 * panels, 8.3 if extra else 4.3), constrained_layout=True)
    gs = fig.add_gridspec(2 if extra else 1, panels)
    axes = [fig.add_subplot(gs[0, i]) for i in range(panels)]
    fig.suptitle(_title_block(ds, seed), fontsize=9)
    dist, ii, jj, vhat = _cut(ds, p, x, y)
    ax = axes[0]
    ax.imshow(contact.T, origin="lower", extent=ext, cmap="Greys", aspect="auto",
              vmin=0, vmax=1.6)
    if "G_front" in ds:
        G = ds["G_front"].values
        ok = np.isfinite(G)
        X, Y = np.meshgrid(x, y, indexing="ij")
        lo, hi = np.percentile(G[ok], [5, 95]) if ok.any() else (0.0, 2.0)
        lo, hi = min(lo, 1.0), max(hi, 1.0)  # keep G = Δγ (balance) inside the scale
        sc = ax.scatter(X[ok], Y[ok], c=np.clip(G[ok], lo, hi), s=4, cmap="coolwarm",
                        marker="s", vmin=lo, vmax=hi)
        fig.colorbar(sc, ax=ax, label="local G/Δγ on the front")
        held = front_cells(contact)[0] & ~ok  # edges held by contact (or unresolved)
        ax.scatter(X[held], Y[held], c="k", s=2, marker="s",
                   label="front without a crack tip")
        if held.any():
            ax.legend(loc="upper right", fontsize=7, markerscale=3)
    if not seed and (ds.attrs.get("velocity_x", 0.0) or ds.attrs.get("velocity_y", 0.0)):
        L = 0.18 * min(np.ptp(x), max(np.ptp(y), 1e-300))
        x0, y0 = x[0] + 0.12 * np.ptp(x), y[0] + 0.12 * np.ptp(y)
        ax.annotate("v", (x0 + L * vhat[0], y0 + L * vhat[1]), (x0, y0), color="C1",
                    arrowprops=dict(arrowstyle="->", color="C1", lw=2), fontsize=10)
    frac = float(ds["area_fraction"]) if "area_fraction" in ds else float(contact.mean())
    tips = ""
    if "crack_tip_length" in ds and float(ds["front_length"]) > 0:
        share = float(ds["crack_tip_length"]) / float(ds["front_length"])
        tips = f"; crack tips {100 * share:.0f} % of front"
    ax.set_title(f"contact (area {frac:.3f}{tips})" if tips
                 else f"contact (area fraction {frac:.3f})")
    ax = axes[1]
    pp = np.ma.masked_where(~contact, p * pu)
    # robust colour scale: isolated tensile spikes at front corners would hide the field
    pv = p[contact] * pu if contact.any() else np.zeros(1)
    vlo, vhi = np.percentile(pv, [1, 99])
    if vlo < 0 < vhi:  # adhesive: tension blue, compression red, p = 0 white
        norm = colors.TwoSlopeNorm(vmin=vlo, vcenter=0.0, vmax=vhi)
        im = ax.imshow(pp.T, origin="lower", extent=ext, cmap="RdBu_r", norm=norm,
                       aspect="auto")
    else:
        im = ax.imshow(pp.T, origin="lower", extent=ext, cmap="magma", aspect="auto",
                       vmin=min(vlo, 0.0), vmax=vhi)
    ax.set_facecolor("0.85")
    fig.colorbar(im, ax=ax, label=pl)
    ax.set_title("pressure (grey: no contact)")
    if panels == 4:
        ax = axes[2]
        gap = np.ma.masked_where(ds["gap"].values <= 0, ds["gap"].values * 1e6)
        norm = colors.LogNorm(vmin=max(float(gap.min()), 1e-6 * float(gap.max())),
                              vmax=float(gap.max())) if gap.count() else None
        im = ax.imshow(gap.T, origin="lower", extent=ext, cmap="viridis", norm=norm,
                       aspect="auto")
        ax.set_facecolor("0.85")
        fig.colorbar(im, ax=ax, label="gap (μm)")
        ax.set_title("gap (log scale; grey: contact)")
    for ax in axes[:-1]:
        _draw_cut(ax, x, y, ii, jj)
        ax.set_xlabel(f"x ({unit})")
        ax.set_ylabel(f"y ({unit})")
    ax = axes[-1]
    on = contact[ii, jj]
    if on.any() and not on.all():  # zoom to the contact along the cut, with a margin
        k = np.flatnonzero(on)
        span = dist[k.max()] - dist[k.min()]
        lim = (dist[k.min()] - 0.6 * span - 2 * abs(dist[1] - dist[0]),
               dist[k.max()] + 0.6 * span + 2 * abs(dist[1] - dist[0]))
    else:
        lim = (dist[0], dist[-1])
    sel = (dist >= lim[0]) & (dist <= lim[1])
    if seed:
        ax.plot(dist[sel], p[ii, jj][sel], "C3-")
        ax.set_ylabel("p/p*")
    else:
        h = ds["heights"].values
        w = h - h.max() + float(ds["penetration"])
        top, slab = -w[ii, jj][sel] * 1e6, -ds["displacement"].values[ii, jj][sel] * 1e6
        rng = max(np.ptp(np.r_[top, slab]), 1e-12)
        hi, lo = top.max() + 0.1 * rng, slab.min() - 0.1 * rng
        ax.fill_between(dist[sel], top, hi, color="0.75", label="rigid indenter")
        ax.fill_between(dist[sel], lo, slab, color="C0", alpha=0.35, label="slab")
        ax.plot(dist[sel], slab, "C0-", lw=1)
        ax.set_ylim(lo, hi)
        ax.set_ylabel("height (μm)")
        ax.legend(loc="best", fontsize=8)
    ax.set_xlabel(f"distance along {'v' if not seed else 'x'} ({unit})")
    ax.set_title("profile cut (dashed on the maps)")
    if extra:
        _distributions(fig, gs, ds, p[contact], ds["x"].values, ds["y"].values)
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def _distributions(fig, gs, ds, p_in, x, y):
    """Second row of a physical state figure: the pressure distribution P(p) in contact,
    the surface's radially averaged power spectrum C(q) and, when adhesive, the distribution
    of G/Δγ along the balanced front."""
    ax = fig.add_subplot(gs[1, 0])
    if p_in.size:
        ax.hist(p_in * 1e-3, bins=60, density=True, color="C3", alpha=0.8)
    ax.axvline(0.0, color="0.4", lw=0.8)
    ax.set_xlabel("pressure in contact (kPa)")
    ax.set_ylabel("P(p) (1/kPa)")
    ax.set_title("pressure distribution")
    ax = fig.add_subplot(gs[1, 1])
    h = ds["heights"].values
    hx, hy = x[1] - x[0], (y[1] - y[0]) if len(y) > 1 else 1.0
    area = hx * hy * h.size
    C = (hx * hy) ** 2 / area * np.abs(np.fft.fft2(h - h.mean())) ** 2  # m⁴
    qx = 2 * np.pi * np.fft.fftfreq(h.shape[0], hx)
    qy = 2 * np.pi * np.fft.fftfreq(h.shape[1], hy)
    q = np.hypot(*np.meshgrid(qx, qy, indexing="ij"))
    ok = q > 0
    if ok.any() and len(y) > 2:
        edges = np.geomspace(q[ok].min(), q[ok].max() * 1.0001, 40)
        k = np.digitize(q[ok], edges) - 1  # bin of each mode
        n = np.bincount(k, minlength=edges.size - 1)
        Cc = np.bincount(k, weights=C[ok], minlength=edges.size - 1) / np.maximum(n, 1)
        qc = np.sqrt(edges[:-1] * edges[1:])
        pos = (n > 0) & (Cc > 1e-30 * max(Cc.max(), 1e-300))
        ax.loglog(qc[pos], Cc[pos], "o-", ms=3)
    ax.set_xlabel("wavenumber |q| (1/m)")
    ax.set_ylabel("C(q) (m⁴)")
    ax.set_title("surface power spectrum (radial mean)")
    if "G_front" in ds:
        ax = fig.add_subplot(gs[1, 2])
        G = ds["G_front"].values
        G = G[np.isfinite(G)]
        if G.size:
            ax.hist(G, bins=40, color="C4", alpha=0.8)
        ax.axvline(1.0, color="0.4", lw=0.8)
        ax.set_xlabel("G/Δγ on the balanced front")
        ax.set_ylabel("front cells")
        ax.set_title("release rate along the front")


def plot_profile_1d(ds, path=None):
    """1D state (seed method): pressure p/p* = −σ/p* (compressive positive, as the 2D maps)
    and displacement u/Λ on the contact; the indenter slides along +x."""
    fig, axes = plt.subplots(1, 2, figsize=(9, 3.6), constrained_layout=True)
    x = ds["x_tilde"].values
    axes[0].plot(x, -ds["sigma_tilde"].values, "C3-")
    axes[0].axhline(0.0, color="0.5", lw=0.8)
    axes[0].set_xlabel("k x (sliding along +x)")
    axes[0].set_ylabel("p/p* (compressive +)")
    axes[0].set_title(f"{ds.attrs.get('model', '')}: status {ds['status'].item()}, "
                      f"ã = {float(ds['a_tilde']):.4g}")
    axes[1].plot(x, ds["u_tilde"].values, "C0-")
    axes[1].set_xlabel("k x (sliding along +x)")
    axes[1].set_ylabel("u/Λ")
    axes[1].set_title(f"ẽ = {float(ds['e_tilde']):.4g}, μ̄ = {float(ds['mu_bar']):.4g}")
    for ax in axes:
        ax.grid(alpha=0.3)
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig
