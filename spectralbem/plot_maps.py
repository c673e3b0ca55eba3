"""The figure of one grid state, drawn by :func:`spectralbem.plotting.plot_contact`.

A title block (scene, material, sliding velocity and its angle, load, μ, area, status; a red
banner and frame when the state is not verified), the contact map with the front coloured
by the local G/Δγ and the sliding direction, the pressure (diverging around p = 0 with
ticks on both sides when adhesive; its colour scale clipped to the 1st-99th percentile with
extend arrows and the clipped extremes named), the gap (log scale), a profile cut through
the highest pressure and, for physical scenes, the pressure distribution, the surface's
power spectrum (a line of text for a surface of a few modes) and the distribution of G/Δγ
along the front.
"""

from __future__ import annotations

import json

import numpy as np

from .bands import front_cells
from .plot_style import ROUND_OFF, _suptitle, plt  # pyplot with the package's backend

#: a surface with fewer distinct wavenumbers than this gets a line of text, not a spectrum
SPECTRUM_MODES = 4


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


def _motion(ds, seed: bool):
    """The sliding direction as (unit vector in the (x, y) plane, angle to x in degrees), or
    None at rest; the seed's scenes slide at ``direction_deg`` to their wave vector, x."""
    if seed:
        if not ds.attrs.get("zeta", 1.0):
            return None
        angle = float(ds.attrs.get("direction_deg", 0.0))
    else:
        vx, vy = float(ds.attrs.get("velocity_x", 0.0)), float(ds.attrs.get("velocity_y", 0.0))
        if vx == 0 and vy == 0:
            return None
        angle = float(np.degrees(np.arctan2(vy, vx)))
    r = np.radians(angle)
    return np.array([np.cos(r), np.sin(r)]), angle


def _title_block(ds, seed: bool) -> str:
    """Scene, material, sliding velocity (and its angle to x), load, μ and contact area."""
    try:
        spec = json.loads(ds.attrs.get("scene", "{}"))
    except ValueError:
        spec = {}
    name = ds.attrs.get("title", "").replace("spectralbem result: ", "") or "state"
    mu = float(ds["mu_bar"] if seed else ds["mu"])
    mu_text = f"{mu:.4g}" if abs(mu) >= ROUND_OFF else "0"
    area = float(ds["area_fraction"]) if "area_fraction" in ds else float(
        ds["contact"].values.mean())
    motion = _motion(ds, seed)
    angle = motion[1] if motion is not None else 0.0
    if seed:
        a = ds.attrs
        oblique = f", v at {angle:.3g}° to the wave vector x" if angle else ""
        return (f"{name}: ζ = {a.get('zeta', float('nan')):g}{oblique}, β = "
                f"{a.get('beta', float('nan')):g}, Γ = {a.get('Gamma', float('nan')):g}, "
                f"p̃ = {float(ds['p_tilde']):.4g}, μ/Λ̃ = {mu_text}, "
                f"ã = {float(ds['a_tilde']):.4g}, status {ds['status'].item()}")
    mat = spec.get("material", {})
    mtext = ", ".join(f"{k} {v:g}" for k, v in mat.items()
                      if k != "kind" and isinstance(v, (int, float)))
    v = float(np.hypot(ds.attrs.get("velocity_x", 0.0), ds.attrs.get("velocity_y", 0.0)))
    return (f"{name} — {mat.get('kind', '')} ({mtext}); v = {v:.3g} m/s"
            + (f" at {angle:.3g}° to x" if angle else "") + "; "
            f"p̄ = {float(ds['mean_pressure']):.4g} Pa; μ = {mu_text}; "
            f"contact area {area:.4f}; {ds['status'].item()}")


def _cut(ds, p, x, y):
    """The profile cut through the highest pressure along the sliding direction (x if at
    rest, and for the seed's y-invariant sinusoid): (distance along it, row and column
    indices)."""
    vx, vy = ds.attrs.get("velocity_x", 0.0), ds.attrs.get("velocity_y", 0.0)
    if vx == 0 and vy == 0:
        vx = 1.0
    hx, hy = x[1] - x[0], (y[1] - y[0]) if len(y) > 1 else 1.0
    i0, j0 = np.unravel_index(np.argmax(p), p.shape)
    s, ii, jj = _cut_along(p, i0, j0, vx / hx, vy / hy)
    norm = max(abs(vx / hx), abs(vy / hy))
    return s * np.hypot(vx / norm, vy / norm), ii, jj


def _cut_label(motion, seed: bool, unit: str) -> str:
    """The cut's axis label, naming the direction it is taken along."""
    angle = motion[1] if motion is not None else 0.0
    if seed:
        along = (f"x, the wave vector (v at {angle:.3g}° to x)" if angle
                 else "x" if motion is None else "x = v")
    else:
        along = ("x (at rest)" if motion is None
                 else f"v, at {angle:.3g}° to x" if angle else "v")
    return f"distance along {along} ({unit})"


def _draw_cut(ax, x, y, ii, jj):
    """The cut's cells as a dashed line on a map (broken where it wraps around the cell)."""
    xs, ys = x[ii], y[jj]
    jump = np.flatnonzero((np.abs(np.diff(xs)) > 0.5 * np.ptp(x))
                          | (np.abs(np.diff(ys)) > 0.5 * max(np.ptp(y), 1e-300))) + 1
    for seg in np.split(np.arange(xs.size), jump):
        ax.plot(xs[seg], ys[seg], "--", color="C2", lw=0.9)


def _velocity_arrow(ax, motion, x, y, seed: bool):
    """The sliding direction as an arrow drawn from a point (its label beside the tail, not
    attached to it, so the direction is exact): in the map's coordinates for a physical
    scene; at the true angle on screen for the seed's strip, whose y is not to scale."""
    vhat, angle = motion
    style = dict(arrowstyle="->", color="C1", lw=2, shrinkA=0, shrinkB=0)
    fx = 0.1 if vhat[0] >= -0.1 else 0.3  # room for the arrow inside the map
    fy = 0.16 if vhat[1] >= -0.1 else 0.36
    text = dict(color="C1", fontsize=9, va="top", ha="left",
                bbox=dict(fc="white", ec="none", alpha=0.7, pad=1))
    if seed:
        from matplotlib.transforms import ScaledTranslation

        tip = ax.transAxes + ScaledTranslation(0.45 * vhat[0], 0.45 * vhat[1],
                                               ax.figure.dpi_scale_trans)
        ax.annotate("", (fx, fy), xycoords=tip, xytext=(fx, fy), textcoords="axes fraction",
                    arrowprops=style)
        label = f"v ({angle:.3g}° to x; y not to scale)" if angle else "v"
    else:
        L = 0.18 * min(np.ptp(x), max(np.ptp(y), 1e-300))
        x0, y0 = x[0] + fx * np.ptp(x), y[0] + fy * np.ptp(y)
        ax.annotate("", (x0 + L * vhat[0], y0 + L * vhat[1]), (x0, y0), arrowprops=style)
        label, fx, fy = (f"v ({angle:.3g}°)" if angle else "v"), x0, y0
    ax.annotate(label, (fx, fy), xycoords="axes fraction" if seed else "data",
                xytext=(0, -5), textcoords="offset points", **text)


def _pressure_text(v: float) -> str:
    """A pressure in Pa with a readable unit (1.35 MPa, 48 kPa, 120 Pa)."""
    a = abs(v)
    return (f"{v / 1e6:.3g} MPa" if a >= 1e6 else f"{v / 1e3:.3g} kPa" if a >= 1e3
            else f"{v:.3g} Pa")


def _pressure_map(fig, ax, p, contact, ext, seed: bool):
    """The pressure in contact (non-contact masked): diverging around p = 0 when adhesive,
    ticked at the scale's ends, half-way and 0 (tension and compression both readable); the
    colour scale clipped to the 1st-99th percentile (isolated tensile spikes at front corners
    would hide the field), with extend arrows and the clipped extremes in the bar's label."""
    from matplotlib import colors, ticker

    pl, pu = ("p/p*", 1.0) if seed else ("pressure (kPa)", 1e-3)
    pp = np.ma.masked_where(~contact, p * pu)
    pv = p[contact] * pu if contact.any() else np.zeros(1)
    vlo, vhi = np.percentile(pv, [1, 99])
    ticks = None
    if vlo < 0 < vhi:  # adhesive: tension blue, compression red, p = 0 white
        norm, cmap = colors.TwoSlopeNorm(vmin=vlo, vcenter=0.0, vmax=vhi), "RdBu_r"
        ticks = [vlo, vlo / 2, 0.0, vhi / 2, vhi]
    else:
        vlo = min(vlo, 0.0)
        norm, cmap = colors.Normalize(vmin=vlo, vmax=vhi), "magma"
    im = ax.imshow(pp.T, origin="lower", extent=ext, cmap=cmap, norm=norm, aspect="auto")
    ax.set_facecolor("0.85")
    low, high = bool(pv.min() < vlo), bool(pv.max() > vhi)
    extend = "both" if low and high else "min" if low else "max" if high else "neither"

    def text(v):
        return f"{v:.3g}" if seed else _pressure_text(v / pu)

    clipped = [f"peak {text(pv.max())}"] * high + [f"min {text(pv.min())}"] * low
    label = pl + ("\nscale clipped: " + ", ".join(clipped) if clipped else "")
    bar = fig.colorbar(im, ax=ax, label=label, extend=extend, ticks=ticks)
    if ticks is not None:
        bar.ax.yaxis.set_major_formatter(ticker.FuncFormatter(lambda v, _: f"{v:.3g}"))
    ax.set_title("pressure (grey: no contact)")


def plot_contact(ds, path=None):
    """See :func:`spectralbem.plotting.plot_contact`."""
    seed = "pressure_tilde" in ds
    scale, unit = (1.0, "k⁻¹") if seed else (1e3, "mm")
    x = ds["x"].values * scale
    y = ds["y"].values * scale
    p = ds["pressure_tilde"].values if seed else ds["pressure"].values
    contact = ds["contact"].values.astype(bool)
    # cell-centred values: the image spans half a cell beyond the first and last centres
    hx = x[1] - x[0] if x.size > 1 else 1.0
    hy = y[1] - y[0] if y.size > 1 else hx
    ext = (x[0] - hx / 2, x[-1] + hx / 2, y[0] - hy / 2, y[-1] + hy / 2)
    panels = 3 if seed or "gap" not in ds else 4
    extra = not seed and "heights" in ds
    fig = plt.figure(figsize=(4.4 * panels, 8.3 if extra else 4.3), constrained_layout=True)
    gs = fig.add_gridspec(2 if extra else 1, panels)
    axes = [fig.add_subplot(gs[0, i]) for i in range(panels)]
    _suptitle(fig, _title_block(ds, seed), ds["status"].item(), fontsize=9)
    dist, ii, jj = _cut(ds, p, x, y)
    motion = _motion(ds, seed)
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
    if motion is not None:
        _velocity_arrow(ax, motion, x, y, seed)
    frac = float(ds["area_fraction"]) if "area_fraction" in ds else float(contact.mean())
    tips = ""
    if "crack_tip_length" in ds and float(ds["front_length"]) > 0:
        share = float(ds["crack_tip_length"]) / float(ds["front_length"])
        tips = f"; crack tips {100 * share:.0f} % of front"
    ax.set_title(f"contact (area {frac:.3f}{tips})" if tips
                 else f"contact (area fraction {frac:.3f})")
    _pressure_map(fig, axes[1], p, contact, ext, seed)
    if panels == 4:
        from matplotlib import colors

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
    _profile(axes[-1], ds, seed, p, contact, dist, ii, jj)
    axes[-1].set_xlabel(_cut_label(motion, seed, unit))
    if extra:
        _distributions(fig, gs, ds, p[contact], ds["x"].values, ds["y"].values)
    if path is not None:
        fig.savefig(path, dpi=110)
    return fig


def _profile(ax, ds, seed, p, contact, dist, ii, jj):
    """The profile cut, zoomed to the contact along it: p/p* (seed) or the rigid indenter
    over the deformed slab (μm)."""
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
    ax.set_title("profile cut (dashed on the maps)")


def _spectrum(h, hx, hy):
    """The surface's power spectrum C (m⁴) at each wavevector's |q| (1/m) of the grid, in
    Persson's normalisation: C(q) = A/((2π)² N²) |FFT(h)|², so that Σ C Δ²q = ⟨h²⟩ with
    Δ²q = (2π)²/A the area per wavevector."""
    C = (hx * hy) / (h.size * (2 * np.pi) ** 2) * np.abs(np.fft.fft2(h - h.mean())) ** 2
    qx = 2 * np.pi * np.fft.fftfreq(h.shape[0], hx)
    qy = 2 * np.pi * np.fft.fftfreq(h.shape[1], hy)
    return np.hypot(*np.meshgrid(qx, qy, indexing="ij")), C


def _distributions(fig, gs, ds, p_in, x, y):
    """Second row of a physical state figure: the pressure distribution P(p) in contact,
    the surface's radially averaged power spectrum C(q) (for a surface of fewer than
    ``SPECTRUM_MODES`` wavenumbers, its modes as text) and, when adhesive, the distribution
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
    q, C = _spectrum(h, hx, hy)
    ok = q > 0
    on = ok & (C > 1e-12 * max(C.max(), 1e-300))  # the modes carrying the power
    digits = 6 - int(np.log10(q[on].max())) if on.any() else 0  # |q| to 6 figures
    modes = np.unique(q[on].round(decimals=digits))
    if modes.size < SPECTRUM_MODES or len(y) <= 2:
        words = {0: "flat surface", 1: "single mode"}.get(modes.size, f"{modes.size} modes")
        lines = [f"|q| = {k:.3g} 1/m (λ = {2e3 * np.pi / k:.3g} mm)" for k in modes[:3]]
        ax.text(0.5, 0.5, "\n".join([words, *lines, "(no spectrum to draw)"]),
                ha="center", va="center", transform=ax.transAxes, fontsize=10)
        ax.set_axis_off()
        ax.set_title("surface power spectrum")
    else:
        edges = np.geomspace(q[ok].min(), q[ok].max() * 1.0001, 40)
        k = np.digitize(q[ok], edges) - 1  # bin of each mode
        n = np.bincount(k, minlength=edges.size - 1)
        Cc = np.bincount(k, weights=C[ok], minlength=edges.size - 1) / np.maximum(n, 1)
        qc = np.sqrt(edges[:-1] * edges[1:])
        pos = (n > 0) & (Cc > 1e-30 * max(Cc.max(), 1e-300))
        ax.loglog(qc[pos], Cc[pos], "o-", ms=3)
        ax.set_xlabel("wavenumber |q| (1/m)")
        ax.set_ylabel("C(q) (m⁴; ∫C d²q = ⟨h²⟩)")
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
