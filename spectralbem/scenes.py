"""Scenes: one study, validated before any heavy work, and ``solve(scene)`` → Dataset.

So far the seed's sinusoid scene in 2D (``Scene.sinusoid``); scene files are still to come.
The scene decides the model: an elastic material never builds the viscoelastic kernel, a
half-space never evaluates S, an adhesiveless scene never runs the energy balance.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .contact import sliding_direction
from .materials import Material
from .spectral import Cell, SpectralOperator
from .surfaces import sinusoid


class SceneError(ValueError):
    """Invalid scene parameter."""


@dataclass
class Scene:
    """A periodic contact problem in dimensionless sinusoid units (k = Λ = E0* = τ = 1)."""

    cell: Cell
    material: Material
    heights: np.ndarray
    velocity: tuple
    dgamma: float
    a0: float
    p_mean: float | None = None
    delta: float | None = None
    kind: str = "custom"
    params: dict = field(default_factory=dict)

    @classmethod
    def sinusoid(cls, zeta: float, beta: float, Gamma: float, *, p_tilde: float | None = None,
                 delta_tilde: float | None = None, a0_tilde: float,
                 cells_per_wavelength: int, ny: int = 8, direction_deg: float = 0.0) -> Scene:
        """The seed scene: h = Λ cos(kx) on an Lx = λ by ny-cell periodic cell, sliding at
        ζ = kvτ along the angle ``direction_deg`` to the wave vector."""
        problems = []
        checks = [("zeta", zeta, 0.0, np.inf), ("beta", beta, 1.0, 1e8),
                  ("Gamma", Gamma, 0.0, 10.0), ("a0_tilde", a0_tilde, 0.0, np.pi),
                  ("cells_per_wavelength", cells_per_wavelength, 16, 1 << 20),
                  ("ny", ny, 1, 4096), ("direction_deg", direction_deg, -360.0, 360.0)]
        for name, v, lo, hi in checks:
            try:
                fv = float(v)
            except (TypeError, ValueError):
                problems.append(f"{name} = {v!r} is not a number")
                continue
            if not (lo <= fv <= hi) or np.isnan(fv):
                problems.append(f"{name} = {v!r} is outside the allowed range [{lo}, {hi}]")
        if (p_tilde is None) == (delta_tilde is None):
            problems.append("give exactly one of p_tilde (load control) and delta_tilde")
        n = int(cells_per_wavelength)
        if not problems and Gamma > 0 and a0_tilde < 2 * np.pi / n * (1 - 1e-9):
            problems.append(f"a0_tilde = {a0_tilde!r} is smaller than one cell "
                            f"({2 * np.pi / n:.4g}); allowed [{2 * np.pi / n:.4g}, π]")
        if problems:
            raise SceneError("; ".join(problems))
        lam = 2 * np.pi
        cell = Cell(lam, lam / n * ny, n, int(ny))
        from .sinusoid1d import dimensionless_material

        mat, v = dimensionless_material(zeta, beta)
        phi = np.radians(direction_deg)
        pm = None if p_tilde is None else 0.5 * float(p_tilde)  # p* = 1/2 in these units
        return cls(cell, mat, sinusoid(cell, 1.0), (v * np.cos(phi), v * np.sin(phi)),
                   np.pi * Gamma, float(a0_tilde), pm, delta_tilde, "sinusoid",
                   dict(zeta=float(zeta), beta=float(beta), Gamma=float(Gamma),
                        a0_tilde=float(a0_tilde), cells_per_wavelength=n, ny=int(ny),
                        direction_deg=float(direction_deg)))


def _edges_y_invariant(mask, offset, cell):
    """Trailing/leading edge distances (l1, l2) from the summit, averaged over rows, with the
    sub-cell offsets of the outer front cells."""
    lam = cell.Lx
    x = (cell.x + lam / 2) % lam - lam / 2
    l1s, l2s = [], []
    for j in range(cell.Ny):
        row = mask[:, j]
        if not row.any() or row.all():
            return np.nan, np.nan
        xs = x[row]
        i_lo = int(np.flatnonzero(row & (x == xs.min()))[0])
        i_hi = int(np.flatnonzero(row & (x == xs.max()))[0])
        s_lo = offset[(i_lo - 1) % cell.Nx, j]
        s_hi = offset[(i_hi + 1) % cell.Nx, j]
        l1s.append(-(xs.min() - cell.hx / 2) + (s_lo if np.isfinite(s_lo) else 0.0))
        l2s.append(xs.max() + cell.hx / 2 + (s_hi if np.isfinite(s_hi) else 0.0))
    return float(np.mean(l1s)), float(np.mean(l2s))


def solve(scene: Scene, *, mask0=None, rtol: float = 1e-10):
    """Solve a scene; returns an xarray Dataset (sinusoid scenes: the 1D method's names)."""
    import xarray as xr

    from .adhesive import solve_adhesive
    from .contact import friction, solve_contact

    op = SpectralOperator(scene.cell, scene.material, velocity=scene.velocity)
    cell, h = scene.cell, scene.heights
    pstar = 0.5
    out = {}
    if scene.dgamma > 0:
        if mask0 is None and scene.kind == "sinusoid":  # start from Johnson's E0 contact
            from . import reference as ref

            pt = scene.p_mean / pstar if scene.p_mean is not None else 0.3
            a = ref.johnson_a(pt, scene.params["Gamma"]) if pt is not None else np.nan
            a = a if np.isfinite(a) else 1.0
            xw = (cell.x + np.pi) % (2 * np.pi) - np.pi
            mask0 = np.repeat((np.abs(xw) < a)[:, None], cell.Ny, axis=1)
        vhat = sliding_direction(op)
        vperp = (-vhat[1], vhat[0])
        obs = {"load": np.ones(cell.shape), "force": -cell.derivative(h, vhat),
               "lateral": -cell.derivative(h, vperp)}
        r = solve_adhesive(op, h, scene.dgamma, scene.a0, penetration=scene.delta,
                           mean_pressure=scene.p_mean, mask0=mask0, rtol=rtol,
                           observables=obs)
        p, mask, delta, status = r.pressure, r.mask, r.penetration, r.status
        a0e = r.a0_effective
        u = op.apply(p)
        if scene.kind == "sinusoid" and status == "partial":
            l1, l2 = _edges_y_invariant(mask, r.offset_out, cell)
            G = []
            # integrated quantities at the sub-cell front: first-order interpolation in the
            # edge position between the base state and its closing (s > 0) or opening (s < 0)
            # layer state, at the same fixed Δ
            base = {k: float(np.sum(p * f)) for k, f in obs.items()}
            corr = dict.fromkeys(obs, 0.0)
            for ci in sorted(r.tests.closing):
                dLc, dUc, _, Ac, oc = r.tests.closing[ci]
                dLo, dUo, _, Ao, oo = r.tests.opening[ci]
                col = r.tests.colour_map[ci]
                s = float(np.nanmean(np.where(col & np.isfinite(r.offset_out), r.offset_out,
                                              np.nan)))
                Gc, Go = dUc / Ac, dUo / Ao
                G.append(Go + (Gc - Go) * (a0e + s) / a0e)  # G at the balanced edge l*
                ref_state = oc if s >= 0 else oo
                for k in obs:
                    corr[k] += abs(s) / a0e * (ref_state[k] - base[k])
            at_front = {k: base[k] + corr[k] for k in obs}
            out["mu_bar_front"] = at_front["force"] / at_front["load"]
            out["mu_bar_lateral_front"] = at_front["lateral"] / at_front["load"]
            if len(G) == 1:
                G = G * 2
            # colour 0 is trailing (v̂·n < 0); for elastic scenes one colour for both edges
            out.update(G1_over_dgamma=G[0] / scene.dgamma, G2_over_dgamma=G[1] / scene.dgamma)
        else:
            l1 = l2 = np.nan
            out.update(G1_over_dgamma=np.nan, G2_over_dgamma=np.nan)
        info = dict(outer_iterations=r.outer_iterations, solves=r.solves, message=r.message,
                    a0_effective=a0e)
    else:
        res = solve_contact(op, h, mean_pressure=scene.p_mean,
                            penetration=None if scene.delta is None else scene.delta, tol=rtol)
        p, mask, delta, u = res.pressure, res.mask, res.penetration, res.displacement
        status = "partial" if res.converged and not res.full_contact else (
            "full_contact" if res.full_contact else "not_converged")
        l1 = l2 = np.nan
        if scene.kind == "sinusoid" and status == "partial":
            zeros = np.zeros(cell.shape)
            l1, l2 = _edges_y_invariant(mask, zeros, cell)
        out.update(G1_over_dgamma=np.nan, G2_over_dgamma=np.nan)
        info = dict(iterations=res.iterations, message=res.message)
    fr = friction(op, h, p, u)
    pm = float(p.mean())
    mu = out.pop("mu_bar_front", fr["mu_profile"])
    mu_lat = out.pop("mu_bar_lateral_front", fr["mu_lateral"])
    out.update(a_tilde=(l1 + l2) / 2, e_tilde=(l2 - l1) / 2, p_tilde=pm / pstar,
               delta_tilde=float(delta), mu_bar=mu, mu_bar_mask=fr["mu_profile"],
               mu_bar_dissipation=fr["mu_dissipation"], mu_bar_lateral=mu_lat)
    G1, G2 = out["G1_over_dgamma"], out["G2_over_dgamma"]
    out["mu_bar_adhesive"] = ((G1 - G2) * scene.dgamma / (cell.Lx * pm)
                              if scene.dgamma > 0 and pm != 0 else np.nan)
    data = {k: ((), float(v), {"units": "1"}) for k, v in out.items()}
    data["status"] = ((), status, {"long_name": "partial | full_contact | detached | "
                                                "not_converged"})
    data["pressure_tilde"] = (("x", "y"), p / pstar, {"long_name": "p/p*", "units": "1"})
    data["contact"] = (("x", "y"), mask.astype(np.int8), {"long_name": "contact mask",
                                                          "units": "1"})
    ds = xr.Dataset(data, coords={"x": ("x", cell.x, {"units": "1", "long_name": "k x"}),
                                  "y": ("y", cell.y, {"units": "1", "long_name": "k y"})})
    ds.attrs.update(model="grid2d", **scene.params, **{k: v for k, v in info.items()})
    return ds
