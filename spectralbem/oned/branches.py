"""Dimensionless problems (seed Section 4 groups) and verified statuses: the branch of
equilibria traced in the half-width ã settles whether a state is partial, unstable, in full
contact or detached (see :mod:`spectralbem.oned`)."""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass

import numpy as np
from scipy.optimize import root

from ..conventions import shown
from ..materials import Elastic, StandardLinearSolid
from .problem import Sinusoid1D, SolveInfo, State

# ---------------------------------------------------------------------------------------------
# dimensionless entry points (seed Section 4 groups; conventions.py)

NXI = 65  # contact-mesh points stored per state (Chebyshev points of the second kind, interior)


def dimensionless_material(zeta: float, beta: float):
    """(material, speed) in units E0 = τ = k = 1: the SLS of Eq. (14) sliding at v = ζ, or the
    elastic E0 (ζ = 0 or β = 1) and E∞ (ζ = inf) limits; ν = 0 so that E0* = E0 = 1."""
    if beta == 1.0 or zeta == 0.0:
        return Elastic(1.0, 0.0), 0.0
    if np.isinf(zeta):
        return Elastic(float(beta), 0.0), 0.0
    return StandardLinearSolid(1.0, float(beta), 1.0, 0.0), float(zeta)


def dimensionless_problem(zeta: float, beta: float, Gamma: float, a0_tilde: float = 0.0, *,
                          adhesive: bool = True, modes: int | None = None,
                          quad: int | None = None,
                          strip_nodes: int = 48) -> Sinusoid1D:
    """Problem in units k = Λ = E0* = τ = 1, so p̃ = 2p, Δγ = πΓ, v = ζ, a0 = ã0.

    ζ = 0 (or β = 1) is the elastic E0 problem and ζ = inf the elastic E∞ problem (still
    normalised with E0).
    """
    _check_inputs(zeta=zeta, beta=beta, Gamma=Gamma, a0_tilde=a0_tilde)
    mat, v = dimensionless_material(zeta, beta)
    return Sinusoid1D(mat, 1.0, 1.0, velocity=v, dgamma=np.pi * Gamma if adhesive else 0.0,
                      a0=a0_tilde, modes=modes, quad=quad, strip_nodes=strip_nodes, E_ref=1.0)


#: the smallest positive ã0 = k a0 the strip quadrature resolves (docs/oned.md, a0)
A0_MIN = 1e-6


def _check_inputs(**kw):
    rng = {"zeta": (0.0, np.inf, True), "beta": (1.0, 1e8, False), "Gamma": (0.0, 10.0, False),
           "a0_tilde": (0.0, 1.0, False)}
    for name, value in kw.items():
        lo, hi, inf_ok = rng[name]
        v = float(value)
        if np.isnan(v) or v < lo or (v > hi and not (inf_ok and np.isinf(v))):
            raise ValueError(f"{name} = {shown(value)} is outside the allowed range [{lo}, {hi}]"
                             + (" or inf" if inf_ok else ""))
        if name == "a0_tilde" and 0.0 < v < A0_MIN:
            raise ValueError(f"a0_tilde = {shown(value)} is outside the allowed range: 0 (the "
                             f"strict limit) or [{A0_MIN:g}, {hi}]; a smaller advance width is not "
                             "resolved by the strip quadrature in double precision")


# ---------------------------------------------------------------------------------------------
# verified statuses: a status names a state that was checked, or says why there is none

#: every status of a 1D state (the long name of the ``status`` variable lists the same)
STATUSES = ("partial", "full_contact", "detached", "unstable", "not_converged")

#: the half-widths ã at which the branch is traced to settle a status (:func:`_branch_verdict`)
VERDICT_GRID = np.concatenate([np.geomspace(0.01, 0.5, 7, endpoint=False),
                               np.linspace(0.5, 3.0, 9)])


@dataclass
class Verdict:
    """A checked outcome: the status, why it holds (or why no state is reported), the
    equilibrium for ``partial`` and ``unstable``, and its largest edge residual."""

    status: str
    reason: str
    state: State | None = None
    residual: float = np.nan
    delta_tilde: float = 0.0  # detached under load control: Δ̃ at the pull-off it detached from


class _Branch:
    """The equilibrium branch p̃(ã), Δ̃(ã) of a dimensionless problem, point by point
    (:func:`branch_point`), each point started from the nearest one solved."""

    def __init__(self, pr: Sinusoid1D):
        self.pr = pr
        self.solved = {}  # ã -> (e, Δ)

    def state(self, a: float) -> State:
        guess = (self.solved[min(self.solved, key=lambda b: abs(b - a))] if self.solved
                 else (0.0, None))
        st = branch_point(self.pr, a, guess)
        if not st.info.converged and guess != (0.0, None):
            st = branch_point(self.pr, a, (0.0, None))
        if st.info.converged:
            self.solved[a] = ((st.l2 - st.l1) / 2, st.penetration)
        return st

    def at(self, a: float):
        """(p̃, Δ̃) of the branch point at ã (nan, nan where none is found)."""
        st = self.state(a)
        if not st.info.converged:
            return np.nan, np.nan
        return st.mean_pressure / self.pr.p_star(), st.penetration / self.pr.amp

    def trace(self, a_grid):
        """The branch on ``a_grid``: (ã, p̃, Δ̃) where a point was found.

        The branch solver can lose the branch between two coarse grid points near the
        snap-in (measured: ζ = 0.1, ã0 = 1e-3, lost after ã = 1.93, found again up to 2.25
        in steps of 0.05): where the load maximum is the last point found and a failed point
        follows, the gap is traced again in smaller steps (warm starts)."""
        a_grid = np.asarray(a_grid, dtype=float)
        vals = np.array([self.at(a) for a in a_grid]).reshape(-1, 2)
        for _ in range(3):
            ok = np.isfinite(vals[:, 0])
            last = np.flatnonzero(ok)
            if last.size == 0 or int(np.argmax(vals[ok, 0])) != last.size - 1 \
                    or last[-1] == a_grid.size - 1:
                break
            fill = np.linspace(a_grid[last[-1]], a_grid[last[-1] + 1], 6)[1:-1]
            a_grid = np.insert(a_grid, last[-1] + 1, fill)
            vals = np.insert(vals, last[-1] + 1, [self.at(a) for a in fill], axis=0)
        ok = np.isfinite(vals[:, 0])
        return a_grid[ok], vals[ok, 0], vals[ok, 1]

    def refine(self, col: int, sign: float, lo: float, hi: float, xatol: float = 1e-5):
        """(ã, value) of the extremum of column ``col`` (0: p̃, 1: Δ̃) in [lo, hi] by a
        bounded scalar search (sign -1: the maximum); the value at an extremum is flat in ã:
        xatol 1e-5 leaves ~1e-10 in the value (1e-4: ~1e-8)."""
        from scipy.optimize import minimize_scalar

        def f(a):
            v = self.at(a)[col]
            return sign * v if np.isfinite(v) else np.inf

        with warnings.catch_warnings():  # a point not found is +inf: the parabola step warns
            warnings.simplefilter("ignore", RuntimeWarning)
            r = minimize_scalar(f, bounds=(lo, hi), method="bounded", options={"xatol": xatol})
        return r.x, sign * r.fun


def _edge_outlook(pr: Sinusoid1D, law) -> str:
    """What an edge does at every admissible penetration (an open gap before closure) when
    its a0 balance has no admissible root: 'advance' (δL < a0Δγ: closing the strip pays) or
    'recede'; 'balance' when a root exists (or a0 = 0, where K is linear in Δ)."""
    K, work, gap = law
    if work is None or np.isfinite(pr.edge_balance_delta(law)) or gap[1] == 0:
        return "balance"
    # no root with an open gap: δL - a0Δγ keeps one sign there; tested just inside
    d = -gap[0] / gap[1] - np.sign(gap[1]) * 1e-2 * pr.amp
    q = work[0] + work[1] * d + work[2] * d * d - pr.a0 * pr.dgamma
    return "advance" if q < 0 else "recede"


def _edge_census(pr: Sinusoid1D, a_grid, n_centres: int = 7) -> str:
    """Why no equilibrium branch was found, from sampled contacts (half-widths ``a_grid``,
    centres across [-a, a]): how many have an edge that advances, or one that recedes, at
    every admissible penetration (:func:`_edge_outlook`; a0 > 0 with adhesion only)."""
    if pr.a0 == 0.0 or pr.dgamma == 0.0:
        return ""
    n = adv = rec = 0
    for a in a_grid:
        span = min(a, 0.49 * pr.lam - a)
        for c in np.linspace(-span, span, n_centres):
            pair = pr.pair_at(a, c)
            out = {_edge_outlook(pr, pr.edge_law(pair, side)) for side in (1, 2)}
            n, adv, rec = n + 1, adv + ("advance" in out), rec + ("recede" in out)
    if rec == n:
        return (f"; at every sampled contact ({n}) an edge releases more than Δγ·a0 at every "
                "admissible penetration: the adhesion is below what the advance width a0 "
                "resolves (a0_tilde = 0, the strict limit, or Gamma = 0 have states)")
    if adv > n // 2:
        return (f"; at {adv} of {n} sampled contacts an edge releases less than Δγ·a0 at "
                "every penetration and advances (strong adhesion: the contact may close "
                "into full contact, not verified)")
    return ""


def _slope(pr: Sinusoid1D, st: State, control: str) -> float:
    """:func:`branch_slope`, on the other side where the forward neighbour is not found."""
    s = branch_slope(pr, st, control)
    return s if np.isfinite(s) else branch_slope(pr, st, control, step=-1e-4)


def _verdict(pr: Sinusoid1D, control: str, value: float, ratio: complex, guess=None, *,
             stability: bool = True) -> Verdict:
    """The verified state at mean pressure p∞ (``control`` 'mean_pressure') or penetration Δ
    ('penetration') of a dimensionless problem (:func:`dimensionless_problem`).

    ``partial``: both edge residuals below the tolerance, no interpenetration outside the
    contact, and (``stability``) on the rising branch, dp̃/dã > 0 under load control or
    dΔ̃/dã > 0 under displacement control (:func:`branch_slope`).  ``full_contact``: without
    adhesion p̃ ≥ |E(kv)|/E0, where the closed-form full-contact pressure is ≥ 0 everywhere;
    with adhesion a load above the largest load of the equilibrium branch (the snap-in of
    the seed's Fig. 13).  ``detached``: no
    compressive load and no stable contact — without adhesion p̃ ≤ 0 or Δ̃ ≤ 0, with adhesion
    a tensile load below the pull-off load of the branch (or Δ̃ below its fixed-grip pull-off).
    ``unstable``: the only equilibrium found lies on the falling branch and the branch does
    not settle the outcome.  ``not_converged`` otherwise.  Loads follow the branch from first
    contact (ã → 0): a full contact formed before would hold any tension (JKR, no flaw).
    """
    load = control == "mean_pressure"
    v = value / (pr.p_star() if load else pr.amp)  # p̃ or Δ̃
    if pr.dgamma == 0.0:
        if load and v >= abs(ratio):
            return Verdict("full_contact", f"p̃ = {v:.6g} ≥ |E(kv)|/E0 = {abs(ratio):.6g}: the "
                           "full-contact pressure p̃ + Re[(E/E0) exp(ikx)] is ≥ 0 everywhere "
                           "(closed form)", residual=0.0)
        if v <= 0.0:
            return Verdict("detached", (f"p̃ = {v:.6g}: no compressive load" if load else
                                        f"Δ̃ = {v:.6g}: the crest does not pass the mean level")
                           + " and no adhesion, so no contact", residual=0.0,
                           delta_tilde=0.0 if load else v)
    st = pr.robust_equilibrium(guess=guess, **{control: value})
    falling = None
    if st.info.converged:
        slope = st.info.branch_slope if st.info.branch_slope is not None else np.inf
        if stability and not (np.isfinite(slope) and slope > 0):
            slope = _slope(pr, st, control)  # adhesiveless (inf: not computed) or not found
        st.info.branch_slope = slope
        scale = pr.k * (pr.p_star() if load else pr.amp)
        if slope > 0 or not stability:
            summ = _summary(pr, st)
            if any(np.isnan(x) for k_, x in summ.items() if stability or k_ != "branch_slope"):
                return Verdict("not_converged", "balanced, but a scalar of the state is nan",
                               residual=st.info.residual)
            return Verdict("partial", f"{st.info.message}; rising branch, "
                           f"d{'p̃' if load else 'Δ̃'}/dã = {slope / scale:.3g} > 0", st,
                           st.info.residual)
        if slope <= 0:
            falling = st
    elif pr.underresolved:  # the branch trace at this resolution would take minutes
        return Verdict("not_converged", f"{st.info.message}; {pr.underresolved}",
                       residual=st.info.residual)
    return _branch_verdict(pr, control, v, st, falling)


def _rise_start(V: np.ndarray) -> int:
    """The index where the traced branch V(ã) stops falling from its smallest contact (the
    first local minimum): the rising part — pull-off to snap-in — and its maximum lie from
    here on.  Near ã → 0 the load falls from 0⁻; where adhesion is strong that start lies
    above the snap-in maximum (Johnson at Γ = 0.1: p̃ ≈ −0.06 at ã = 0.02, maximum −0.0809),
    and the branch's global maximum was taken for the snap-in."""
    j = 0
    while j + 1 < V.size and V[j + 1] <= V[j]:
        j += 1
    return j


def _branch_verdict(pr: Sinusoid1D, control: str, v: float, st: State, falling) -> Verdict:
    """:func:`_verdict` where the direct search found no stable equilibrium: the branch is
    traced on :data:`VERDICT_GRID` and the control value ``v`` (p̃ or Δ̃) placed on it."""
    from scipy.optimize import brentq

    load = control == "mean_pressure"
    col, name = (0, "p̃") if load else (1, "Δ̃")
    note = ""
    if falling is not None:
        s = falling.info.branch_slope / (pr.k * (pr.p_star() if load else pr.amp))
        note = (f"; the equilibrium found at ã = {pr.k * falling.domain.a:.4g} lies on the "
                f"falling branch (d{name}/dã = {s:.3g} ≤ 0: unstable under "
                f"{'load' if load else 'displacement'} control)")

    def unsettled(why):
        if falling is not None:
            return Verdict("unstable", why + note, falling, falling.info.residual)
        return Verdict("not_converged", f"{why}; direct search: {st.info.message}",
                       residual=st.info.residual)

    br = _Branch(pr)
    A, P, D = br.trace(VERDICT_GRID / pr.k)
    if A.size == 0:
        return unsettled(f"no equilibrium branch found (ã from {VERDICT_GRID[0]:g} to "
                         f"{VERDICT_GRID[-1]:g}){_edge_census(pr, VERDICT_GRID / pr.k)}")
    V = P if load else D
    j0 = _rise_start(V)
    if j0 + int(np.argmax(V[j0:])) == A.size - 1:  # still rising at the end: on to 99.6 %
        A2, P2, D2 = br.trace(np.linspace(A[-1], 0.498 * pr.lam, 5)[1:])
        A, P, D = (np.concatenate(z) for z in ((A, A2), (P, P2), (D, D2)))
        V = P if load else D
    n = A.size
    span = f"(the branch traced from ã = {pr.k * A[0]:.3g} to {pr.k * A[-1]:.3g})"

    def around(idx, sign):  # the extremum near A[idx] refined (only where it decides)
        lo, hi = (A[idx - 1] if idx > 0 else A[0] / 10), A[min(idx + 1, n - 1)]
        a_, v_ = br.refine(col, sign, lo, hi, xatol=1e-4)
        return (a_, v_) if sign * v_ <= sign * V[idx] else (A[idx], V[idx])

    # the rising part: from the smallest value before the largest (the pull-off) up to it,
    # past the fall from the smallest contact
    j0 = _rise_start(V)
    i = j0 + int(np.argmax(V[j0:]))
    j = int(np.argmin(V[: i + 1]))
    nodes, vals = list(A[j: i + 1]), list(V[j: i + 1])
    if v > V[i]:
        a_hi, v_hi = around(i, -1.0) if i < n - 1 else (A[i], V[i])
        if v > v_hi:
            if not load:
                return unsettled(f"Δ̃ = {v:.6g} is above the largest Δ̃ = {v_hi:.6g} of the "
                                 f"branch {span}")
            if pr.dgamma == 0.0:  # without adhesion full contact is p̃ ≥ |E(kv)|/E0 exactly
                return unsettled(f"p̃ = {v:.6g} is above the largest load {v_hi:.6g} of the "
                                 f"branch {span} but below |E(kv)|/E0")
            end = (" (the branch still rises at 99.6 % of λ, counted as full contact)"
                   if i == n - 1 else "")
            return Verdict("full_contact", f"p̃ = {v:.6g} exceeds the largest load of the "
                           f"equilibrium branch, p̃ = {v_hi:.6g} at ã = {pr.k * a_hi:.4g} "
                           f"{span}{end}: no partial equilibrium carries it, the contact "
                           "snaps into full contact (seed Fig. 13)" + note, residual=0.0)
        if a_hi > nodes[-1]:
            nodes, vals = nodes + [a_hi], vals + [v_hi]
        else:
            nodes, vals = nodes[:-1] + [a_hi], vals[:-1] + [v_hi]
    if v < V[j]:
        a_lo, v_lo = around(j, 1.0)
        if v < v_lo:
            if load and v > 0:
                return unsettled(f"p̃ = {v:.6g} > 0 is below the smallest load {v_lo:.6g} of "
                                 f"the branch {span}")
            what = (f"the tensile load p̃ = {v:.6g} is below the pull-off load p̃ = {v_lo:.6g}"
                    if load else
                    f"Δ̃ = {v:.6g} is below the fixed-grip pull-off Δ̃ = {v_lo:.6g}")
            return Verdict("detached", f"{what}, the smallest value before the rise of the "
                           f"branch, at ã = {pr.k * a_lo:.4g} {span}: no stable contact"
                           + note, residual=0.0, delta_tilde=br.at(a_lo)[1] if load else v)
        if a_lo < nodes[0]:
            nodes, vals = [a_lo] + nodes, [v_lo] + vals
        else:
            nodes, vals = [a_lo] + nodes[1:], [v_lo] + vals[1:]

    # on the rising part: bracket on the traced points and solve
    def gap(a):
        x = br.at(a)[col]
        if not np.isfinite(x):
            raise ValueError("no branch point")
        return x - v

    nodes, vals = np.array(nodes), np.array(vals)
    for k in np.flatnonzero((vals[:-1] <= v) & (vals[1:] >= v)):
        try:
            a_star = brentq(gap, nodes[k], nodes[k + 1], xtol=1e-12)
        except ValueError:  # a point in the bracket not found
            continue
        pt = br.state(a_star)
        if not pt.info.converged:
            continue
        ctl = {control: v * (pr.p_star() if load else pr.amp)}
        eq = pr.equilibrium(guess=(pt.l1, pt.l2), **ctl)  # the same residual test as above
        if not eq.info.converged:
            continue
        eq.info.branch_slope = _slope(pr, eq, control)
        if eq.info.branch_slope > 0:
            s = eq.info.branch_slope / (pr.k * (pr.p_star() if load else pr.amp))
            return Verdict("partial", f"{eq.info.message}; found on the rising branch "
                           f"by tracing {name}(ã), d{name}/dã = {s:.3g} > 0" + note, eq,
                           eq.info.residual)
    return unsettled(f"{name} = {v:.6g} lies on the rising part of the branch {span} "
                     f"(from {vals[0]:.6g} to {vals[-1]:.6g}), but no stable equilibrium was "
                     "found there")


def _quotient(num: float, den: float) -> float:
    """num/den, with 0/0 = 0 (no force at no load) and ±inf for a finite num at den = 0."""
    if den != 0.0:
        return num / den
    return 0.0 if num == 0.0 else math.copysign(np.inf, num)


def _summary(pr: Sinusoid1D, st: State) -> dict:
    """Dimensionless scalars of a state (k = Λ = E0* = 1 units)."""
    k, lam = pr.k, pr.lam
    pstar = pr.p_star()
    control, value = st.info.control
    # the prescribed load, not its rounding (μ̄ at p̃ = 0 is then ±inf, not F/1e-19)
    pm = value if control == "mean_pressure" and value is not None else st.mean_pressure
    out = {
        "a_tilde": k * (st.l1 + st.l2) / 2, "e_tilde": k * (st.l2 - st.l1) / 2,
        "p_tilde": pm / pstar, "delta_tilde": st.penetration / pr.amp,
        # an elastic contact is symmetric: no friction (the quadrature leaves ~1e-17, which
        # at zero load would read as an infinite μ̄); viscoelastic at zero load: ±inf
        "mu_bar": (_quotient(pr.friction_force(st), lam * pm) / (k * pr.amp)
                   if pr.kernel.visco else 0.0),
        "K1": st.K[0], "K2": st.K[1],
    }
    slope = st.info.branch_slope if st.info.branch_slope is not None else np.nan
    out["branch_slope"] = slope / (k * (pstar if control == "mean_pressure" else pr.amp))
    if pr.dgamma > 0 and pr.a0 > 0 and st.work[0] is not None:
        G1, G2 = (ew.dU / pr.a0 for ew in st.work)
    elif pr.dgamma > 0:  # a0 = 0: strict limit, δL_P → 0 and G_i = K_i²/(2E_tip*)
        G1, G2 = (K * abs(K) / (2 * pr.Estar_tip) for K in st.K)
    if pr.dgamma > 0:
        out.update(G1_over_dgamma=G1 / pr.dgamma, G2_over_dgamma=G2 / pr.dgamma,
                   mu_bar_adhesive=(_quotient(G1 - G2, k * pr.amp * lam * pm)
                                    if pr.kernel.visco else 0.0))
    else:  # no adhesion: the edges close with K = 0 and release nothing
        out.update(G1_over_dgamma=0.0, G2_over_dgamma=0.0, mu_bar_adhesive=0.0)
    return out


def branch_point(pr: Sinusoid1D, a: float, guess=(0.0, None)):
    """Equilibrium at half-width a: the eccentricity e and penetration Δ at which both edges
    balance.  Returns State (``info.converged``).

    The state is linear in Δ for a fixed domain, so for each trial e the trailing-edge balance
    gives Δ in closed form (:meth:`Sinusoid1D.edge_balance_delta`) and only the leading-edge
    residual is left: a scalar secant search in e, which at fixed a costs no domain build
    (:meth:`Sinusoid1D.shape`).  A 2D Newton search in (e, Δ) is the fallback.
    """
    e, d, res, message = _branch_edges(pr, a, guess)
    st = pr.state_of(pr.pair_at(a, e), penetration=d)
    if pr.dgamma and pr.a0:
        pr.release_rates(st)
    over = pr.interpenetration(st)
    if over > 1e-6:  # both edges balance, but the surface crosses the profile elsewhere
        message = f"inadmissible: interpenetrates by {over:.1e} Λ outside the contact"
    st.info = SolveInfo(converged=bool(res < 1e-8 and over <= 1e-6), message=message,
                        residual=float(res), interpenetration=over)
    return st


def branch_slope(pr: Sinusoid1D, st: State, control: str, step: float = 1e-4) -> float:
    """d p∞/d a (load control) or d Δ/d a (displacement control) along the equilibrium
    branch at the state ``st``, one-sided over a step of ``step``·λ in the half-width.

    The rising branch (slope > 0) is the one reached by loading from first contact: in the
    elastic limits it is the stable branch of Johnson (1995) under that control (JKR's
    criterion), and beyond the snap-in maximum the load falls again toward full contact on
    the unstable branch.  nan if the neighbouring branch point is not found."""
    a = st.domain.a + step * pr.lam
    e, d, res, _ = _branch_edges(pr, a, (st.domain.c, st.penetration))
    if not res < 1e-8:
        return np.nan
    if control == "penetration":
        return float((d - st.penetration) / (step * pr.lam))
    p = pr.state_of(pr.pair_at(a, e), penetration=d).mean_pressure
    return float((p - st.mean_pressure) / (step * pr.lam))


def _branch_edges(pr: Sinusoid1D, a: float, guess):
    """(e, Δ, residual, message) of the equilibrium at half-width a (:func:`branch_point`)."""
    from scipy.optimize import root_scalar

    e0, d0 = guess
    # a contact may lie wholly on one side of the crest (small, fast contacts): only its span
    # and the position of its centre within the period are limited
    def ok_span(e):
        return 2 * a < 0.999 * pr.lam and abs(e) < 0.5 * pr.lam

    last = {}

    def F(e):
        if not ok_span(e):
            return np.nan
        pair = pr.pair_at(a, e)
        d = pr.edge_balance_delta(pr.edge_law(pair, 1))
        if not np.isfinite(d):
            return np.nan
        last[e] = d
        return pr.edge_residual(pr.edge_law(pair, 2), d, a)

    res = np.inf
    try:
        with warnings.catch_warnings():  # "tolerance reached": judged by the residual below
            warnings.simplefilter("ignore", RuntimeWarning)
            sol = root_scalar(F, x0=e0, x1=e0 + 1e-3 * a, method="secant", xtol=1e-13,
                              rtol=1e-13, maxiter=40)
        if sol.converged and np.isfinite(sol.root):
            e = sol.root
            res = abs(F(e))  # (the secant's last iterate is not evaluated)
    except (ValueError, ArithmeticError):
        pass
    if res < 1e-8:
        d, message = last[e], "secant in e, Δ from the trailing edge"
    else:  # fallback: Newton-type search in (e, Δ) on both residuals
        if d0 is None:
            d0 = pr.amp * np.sin(pr.k * a / 2) ** 2

        def F2(y):
            e, d = y
            if not ok_span(e):
                return np.array([1e3, 1e3])
            return pr._residual((a, e), "penetration", d)

        sol2 = root(F2, np.array([e0, d0], float), method="hybr", options={"xtol": 1e-12})
        (e, d), res, message = sol2.x, float(np.max(np.abs(sol2.fun))), sol2.message
    return e, d, res, message
