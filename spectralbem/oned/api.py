"""Entry points of the 1D method: :func:`solve`, :func:`sweep`, :func:`special_points`
(dimensionless, k = Λ = E0* = 1 units; see :mod:`spectralbem.oned`)."""

from __future__ import annotations

import numpy as np

from ..conventions import shown
from .branches import (
    NXI,
    _Branch,
    _quotient,
    _rise_start,
    _summary,
    _verdict,
    dimensionless_problem,
)

SCALARS = {
    "a_tilde": "dimensionless contact semi-width k a",
    "e_tilde": "dimensionless eccentricity k e (> 0: toward the leading edge)",
    "p_tilde": "dimensionless mean pressure 2(1-ν²)p∞/(E0 k Λ) carried by the state (0 "
               "when detached; the prescribed one is the attribute prescribed_p_tilde)",
    "delta_tilde": "dimensionless penetration Δ/Λ (mean-level gauge; detached under load "
                   "control: the Δ/Λ of the pull-off the contact let go at)",
    "mu_bar": "reduced friction coefficient μ/Λ̃, Eq. (19), (22)",
    "mu_bar_adhesive": "reduced adhesive friction (G1-G2)/(Λ̃ λ p∞), Eq. (23)",
    "G1_over_dgamma": "energy release rate at the trailing (opening) edge, Eq. (20) (0: no "
                      "edge, or no adhesion)",
    "G2_over_dgamma": "energy release rate at the leading (closing) edge, Eq. (21) (0: no "
                      "edge, or no adhesion)",
    "a_tilde_adhesiveless": "adhesiveless k a at the same load",
    "e_tilde_adhesiveless": "adhesiveless k e at the same load",
    "mu_bar_adhesiveless": "adhesiveless μ/Λ̃ at the same load",
    "branch_slope": "dp̃/dã (load control) or dΔ̃/dã (displacement control) along the "
                    "equilibrium branch: > 0 on the rising (stable) branch; 0 where there "
                    "is no partial branch (full contact, detached: ã fixed)",
}


def solve(zeta: float, beta: float, Gamma: float, *, p_tilde: float | None = None,
          delta_tilde: float | None = None, a0_tilde: float, modes: int | None = None, guess=None,
          adhesiveless_reference: bool = True, quad: int | None = None):
    """One state of the seed's sinusoid problem; returns an xarray Dataset.

    Give exactly one of ``p_tilde`` (load control) and ``delta_tilde`` (displacement control,
    Δ̃ < 1: in the mean-level gauge Δ̃ = 1 is full contact at any load).
    ``a0_tilde`` = k a0 is the advance width of the edge energy balance (0: strict SIF limit).
    The prescribed value is the attribute ``prescribed_p_tilde`` or ``prescribed_delta_tilde``;
    the scalars are the state's (a detached state carries no load: p_tilde 0).
    ``guess`` = (k l1, k l2) for continuation.  Scalars: a_tilde, e_tilde, p_tilde,
    delta_tilde, mu_bar, mu_bar_adhesive, G1_over_dgamma, G2_over_dgamma, branch_slope,
    status, and the adhesiveless a, e, μ at the same load; fields sigma_tilde (= σ/p* = -p̃)
    and u_tilde (= u/Λ) on the contact mesh x_tilde (the period for full contact and
    detached states).  The status is verified (:func:`_verdict`), its reason is the
    ``solver_message`` attribute; no scalar of a partial, full_contact, detached or unstable
    state is nan (not_converged: all nan).
    """
    import xarray as xr

    from ..io import STATUS, attrs

    if (p_tilde is None) == (delta_tilde is None):
        raise ValueError("give exactly one of p_tilde (load control) and delta_tilde")
    for name, v in (("p_tilde", p_tilde), ("delta_tilde", delta_tilde)):
        if v is not None and not np.isfinite(v):
            raise ValueError(f"{name} = {shown(v)} must be finite")
    if delta_tilde is not None and delta_tilde >= 1.0:
        raise ValueError(f"delta_tilde = {shown(delta_tilde)} is outside the allowed range "
                         "(-inf, 1): Δ̃ = 1 is full contact at an undetermined load (the mean "
                         "gap vanishes) and no state has Δ̃ > 1; use p_tilde")
    pr = dimensionless_problem(zeta, beta, Gamma, a0_tilde, adhesive=Gamma > 0, modes=modes,
                               quad=quad)
    ratio = _modulus_ratio(zeta, beta)
    control, value = (("mean_pressure", p_tilde * pr.p_star()) if p_tilde is not None
                      else ("penetration", delta_tilde * pr.amp))
    vd = _verdict(pr, control, value, ratio, guess)
    if vd.status in ("full_contact", "detached"):
        vals, x, p, u = _closed_form(vd.status, p_tilde, vd.delta_tilde, ratio)
        edges = (np.pi, np.pi) if vd.status == "full_contact" else (0.0, 0.0)
    else:
        st = vd.state
        vals = _summary(pr, st) if st is not None else dict.fromkeys(
            ("a_tilde", "e_tilde", "p_tilde", "delta_tilde", "mu_bar", "branch_slope",
             "G1_over_dgamma", "G2_over_dgamma", "mu_bar_adhesive"), np.nan)
        if st is not None:
            xi = np.cos(np.pi * np.arange(1, NXI + 1) / (NXI + 1))[::-1]
            x = st.domain.c + st.domain.a * xi
            p = st.domain.pressure(st.coef, x) / pr.p_star()
            u = pr.w(x, st.penetration) / pr.amp
            x = x * pr.k
            edges = (st.l1 * pr.k, st.l2 * pr.k)
        else:
            x = np.linspace(-np.pi, np.pi, NXI)
            p = u = np.full(NXI, np.nan)
            edges = (np.nan, np.nan)
    if adhesiveless_reference:
        pt = p_tilde if p_tilde is not None else vals["p_tilde"]
        vals.update(_adhesiveless_reference(zeta, beta, Gamma, pt, ratio, modes, quad))
    data = {k_: ((), float(v), {"long_name": SCALARS.get(k_, k_), "units": "1"})
            for k_, v in vals.items() if k_ not in ("K1", "K2")}
    data["status"] = ((), vd.status, attrs(STATUS))
    data["sigma_tilde"] = (("x",), -p, {"long_name": "normal stress σ/p* = -p̃", "units": "1"})
    data["u_tilde"] = (("x",), u, {"long_name": "surface displacement u/Λ on the contact "
                                                "(the period: full contact, detached)",
                                   "units": "1"})
    ds = xr.Dataset(data, coords={"x_tilde": (("x",), x, {"long_name": "k x", "units": "1"})})
    ds.attrs.update(model="sinusoid1d", zeta=float(zeta), beta=float(beta),
                    Gamma=float(Gamma), a0_tilde=float(a0_tilde),
                    control="load" if p_tilde is not None else "displacement",
                    **{f"prescribed_{name}": float(v) for name, v in (
                        ("p_tilde", p_tilde), ("delta_tilde", delta_tilde)) if v is not None},
                    modes=pr.M, quad=pr.Q,
                    converged=int(vd.status in ("partial", "full_contact", "detached")),
                    solver_message=vd.reason, residual=float(vd.residual),
                    l1_tilde=float(edges[0]), l2_tilde=float(edges[1]))
    return ds


def _adhesiveless_reference(zeta, beta, Gamma, pt, ratio, modes, quad) -> dict:
    """The adhesiveless ã, ẽ, μ̄ at the load p̃ ``pt``, verified as in :func:`solve` (nan
    without a load or where no state is found)."""
    keys = ("a_tilde_adhesiveless", "e_tilde_adhesiveless", "mu_bar_adhesiveless")
    if pt is None or not np.isfinite(pt):
        return dict.fromkeys(keys, np.nan)
    ref = dimensionless_problem(zeta, beta, Gamma, 0.0, adhesive=False, modes=modes, quad=quad)
    vd = _verdict(ref, "mean_pressure", pt * ref.p_star(), ratio, stability=False)
    if vd.status in ("full_contact", "detached"):
        vals = _closed_form(vd.status, pt, vd.delta_tilde, ratio)[0]
    elif vd.status == "partial":
        vals = _summary(ref, vd.state)
    else:
        return dict.fromkeys(keys, np.nan)
    return dict(zip(keys, (vals["a_tilde"], vals["e_tilde"], vals["mu_bar"]), strict=True))


def _modulus_ratio(zeta, beta) -> complex:
    """E(ζ)/E0 of the SLS at ω = kv (seed convention)."""
    if zeta == 0 or beta == 1:
        return 1.0 + 0j
    if np.isinf(zeta):
        return complex(beta)
    return (1 - 1j * zeta) / (1 - 1j * zeta / beta)


def _closed_form(status: str, p_tilde, delta_tilde, ratio):
    """(scalars, k x, p̃, u/Λ) of a full contact or detached state over one period.

    Full contact (load control; docs/derivations.md §7): p̃(x) = p̃∞ + Re[(E/E0) e^{ikx}],
    μ/Λ̃ = -Im[E/E0]/(2p̃∞), Δ̃ = 1 (zero-mean gauge: the mean gap Λ - Δ vanishes), no edges
    (G = 0, no adhesive friction).  Detached: no contact, no pressure, a flat surface: it carries
    no load (p̃ = 0, also where a tensile p̃ was prescribed), with ``delta_tilde`` the
    prescribed Δ̃ or, under load control, the Δ̃ of the pull-off (0 without adhesion).  ã does
    not change with the load: branch_slope 0 (no partial branch)."""
    x = np.linspace(-np.pi, np.pi, NXI)
    if status == "full_contact":
        p = p_tilde + np.real(ratio * np.exp(1j * x))
        vals = dict(a_tilde=np.pi, e_tilde=0.0, p_tilde=p_tilde, delta_tilde=1.0,
                    mu_bar=_quotient(-np.imag(ratio), 2 * p_tilde), u=np.cos(x))
    else:
        p = np.zeros(NXI)
        vals = dict(a_tilde=0.0, e_tilde=0.0, p_tilde=0.0,
                    delta_tilde=delta_tilde, mu_bar=0.0, u=np.zeros(NXI))
    u = vals.pop("u")
    vals.update(mu_bar_adhesive=0.0, G1_over_dgamma=0.0, G2_over_dgamma=0.0,
                branch_slope=0.0)
    return {k_: float(v) for k_, v in vals.items()}, x, p, u


def sweep(zeta, beta: float, Gamma: float, *, p_tilde=None, delta_tilde=None, a0_tilde: float,
          modes: int | None = None, progress: bool = False):
    """ζ sweep with continuation from the previous point; one Dataset with dimension zeta.

    Points are solved in increasing ζ, each started from the previous converged edges;
    a point that fails is retried from the elastic guess, and a start that lands on the
    falling (unstable) branch gives way to one that reaches the rising branch
    (:meth:`Sinusoid1D.robust_equilibrium`; ``branch_slope`` is reported).
    """
    import xarray as xr

    zetas = np.atleast_1d(np.asarray(zeta, dtype=float))
    order = np.argsort(zetas)
    results = [None] * zetas.size
    guess = None
    it = order
    if progress:  # a bar on a terminal, plain lines elsewhere
        from ..progress import progress_bar

        it = progress_bar(order, desc="zeta sweep")
    for i in it:
        ds = solve(zetas[i], beta, Gamma, p_tilde=p_tilde, delta_tilde=delta_tilde,
                   a0_tilde=a0_tilde, modes=modes, guess=guess)
        if ds["status"].item() != "partial" and guess is not None:
            ds = solve(zetas[i], beta, Gamma, p_tilde=p_tilde, delta_tilde=delta_tilde,
                       a0_tilde=a0_tilde, modes=modes)
        if ds["status"].item() == "partial":
            guess = (ds.attrs["l1_tilde"], ds.attrs["l2_tilde"])
        results[i] = ds.drop_vars(["sigma_tilde", "u_tilde", "x_tilde"])
    out = xr.concat(results, dim="zeta", combine_attrs="drop_conflicts")
    return out.assign_coords(zeta=("zeta", zetas, {"long_name": "ζ = k v τ", "units": "1"}))


# ---------------------------------------------------------------------------------------------
# the equilibrium branch parametrised by the contact size (pull-off, toughness, snap-in)


def special_points(zeta: float, beta: float, Gamma: float, *, a0_tilde: float,
                   modes: int | None = None, n: int = 40, cheb: int = 20):
    """Pull-off (load and fixed Δ), zero-load contact, snap-in to full contact and toughness.

    Traces the branch in ã (grid refined toward small ã), refines each extremum by a bounded
    scalar minimisation, and evaluates the toughness of Eq. (24), T̃ = 2π∫ p̃ dΔ̃ from p̃ = 0 to
    the fixed-Δ pull-off, exactly on Chebyshev fits of p̃(ã) and Δ̃(ã) through ``cheb`` points.
    Returns a dict with the keys of :func:`spectralbem.reference.johnson_special_points`;
    an extremum the trace does not verify (at an end of the part of the branch it found) is
    nan, and so is what depends on it.  Raises ValueError, naming the inputs, where no
    equilibrium branch is found.
    """
    from numpy.polynomial import chebyshev as C
    from scipy.optimize import brentq

    pr = dimensionless_problem(zeta, beta, Gamma, a0_tilde, modes=modes)
    a_grid = np.concatenate([np.geomspace(0.02, 0.5, n // 2, endpoint=False),
                             np.linspace(0.5, 3.0, n // 2)])
    br = _Branch(pr)
    at = br.at
    A, P, D = br.trace(a_grid)
    if A.size == 0:
        raise ValueError(f"no equilibrium branch found for zeta = {shown(zeta)}, beta = "
                         f"{shown(beta)}, Gamma = {shown(Gamma)}, a0_tilde = {shown(a0_tilde)} "
                         f"(ã traced from {a_grid[0]:g} to {a_grid[-1]:g})")

    def refine(col, idx, sign):
        return br.refine(col, sign, A[max(idx - 1, 0)], A[min(idx + 1, A.size - 1)])

    # the snap-in point is the branch's load maximum; beyond it (toward full contact) the
    # load falls again on an unstable branch, possibly below the pull-off load: the minima
    # are sought on the part of the branch before the maximum
    j0 = _rise_start(P)  # past the fall from the smallest contact (strong adhesion)
    imax = j0 + int(np.argmax(P[j0:]))
    interior = 0 < imax < A.size - 1
    a_pmax, p_max = refine(0, imax, -1.0) if interior else (np.nan, np.nan)
    before = A <= A[imax] if interior else np.ones(A.size, bool)

    def minimum(col, V):
        """The refined minimum of V before the snap-in; nan where it is an end of the part of
        the branch the trace found (the branch still falls where the trace lost it, or rises
        from where it first found it, below the grid's start: no minimum is verified)."""
        k = int(np.argmin(np.where(before, V, np.inf)))
        if k == A.size - 1:
            return np.nan, np.nan
        a_, v_ = refine(col, k, 1.0)
        lost_below = A[0] > a_grid[0] * (1 + 1e-9)
        if k == 0 and lost_below and abs(a_ - A[0]) <= 1e-3 * (A[1] - A[0]):
            return np.nan, np.nan
        return a_, v_

    a_pmin, p_min = minimum(0, P)
    a_dmin, d_min = minimum(1, D)
    cross = np.flatnonzero((P[:-1] < 0) & (P[1:] > 0) & (A[:-1] >= a_pmin))
    a_zero = (brentq(lambda a: at(a)[0], A[cross[0]], A[cross[0] + 1], xtol=1e-12)
              if cross.size else np.nan)
    T = np.nan
    if np.isfinite(a_zero):
        nodes = 0.5 * (a_zero + a_dmin) + 0.5 * (a_zero - a_dmin) * np.cos(
            np.pi * (np.arange(cheb) + 0.5) / cheb)
        pv = np.array([at(a) for a in nodes])
        t = (2 * nodes - a_zero - a_dmin) / (a_zero - a_dmin)
        cp, cd = C.chebfit(t, pv[:, 0], cheb - 1), C.chebfit(t, pv[:, 1], cheb - 1)
        integrand = C.chebint(C.chebmul(cp, C.chebder(cd)))
        T = 2 * np.pi * float(C.chebval(-1.0, integrand) - C.chebval(1.0, integrand))
    return dict(a_pmin=a_pmin, p_min=p_min, a_pmax=a_pmax, p_max=p_max, a0=a_zero,
                a_dmin=a_dmin, delta_min=d_min,
                p_dmin=at(a_dmin)[0] if np.isfinite(a_dmin) else np.nan, T=T,
                branch={"a_tilde": A, "p_tilde": P, "delta_tilde": D})
