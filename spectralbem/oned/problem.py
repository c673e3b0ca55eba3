"""The 1D adhesive problem of a sinusoid on a half-plane: states on a domain, the edge
energy balance of Eqs. (3), (7)-(10), (16)-(17) with advance width a0, equilibrium and
friction (see :mod:`spectralbem.oned`)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft
from scipy.optimize import root
from scipy.special import roots_jacobi

from ..conventions import control as one_control
from ..materials import Material
from .domain import Domain
from .kernel import Kernel1D


@dataclass
class EdgeWork:
    dL: float  # Eq. (8): work of closing the strip (J/m per unit length)
    dU: float  # Eq. (9)
    dLP: float  # Eq. (10)
    gap_sign: float = 1.0  # sign of ∫ g₋ on the strip: -1 means the base state interpenetrates


class _Balanced(Exception):
    """Raised by the residual of :meth:`Sinusoid1D.equilibrium` once both edges balance."""

    def __init__(self, x, fun):
        super().__init__("balanced")
        self.x, self.fun = x, fun


@dataclass
class _Shape:
    """A domain's half-width-only data (:meth:`Sinusoid1D.shape`): the domain centred at 0,
    the solutions of Eq. (15) for the right-hand sides cos kaξ − 1, sin kaξ and 1 (columns),
    and the response matrices of the edge strips by (side, a0)."""

    domain: Domain
    sol: np.ndarray
    strips: dict = field(default_factory=dict)


@dataclass
class SolveInfo:
    """How :meth:`Sinusoid1D.equilibrium` found a state: whether both edges balance within
    its tolerance (``converged``, with the reason), the evaluations, the largest and both
    edge residuals, the control ``(name, value)``, the interpenetration outside the contact
    (units of Λ) and, once computed, the slope of the equilibrium branch (None before)."""

    converged: bool = False
    message: str = ""
    nfev: int = 0
    residual: float = float("nan")
    residuals: tuple = ()
    control: tuple = ("mean_pressure", None)
    interpenetration: float = 0.0
    branch_slope: float | None = None


@dataclass
class State:
    domain: Domain
    coef: np.ndarray
    penetration: float
    mean_pressure: float
    K: tuple
    work: tuple = (None, None)
    info: SolveInfo = field(default_factory=SolveInfo)

    @property
    def l1(self):
        return self.domain.l1

    @property
    def l2(self):
        return self.domain.l2


class Sinusoid1D:
    """Adhesive (or adhesiveless) sliding contact of h = Λ cos(kx) on a half-plane.

    Parameters (SI units)
    ---------------------
    material : any :class:`~spectralbem.materials.Material`
    k, amplitude : wavevector 2π/λ (1/m) and amplitude Λ (m)
    velocity : sliding speed v (m/s), the indenter moves toward +x; v = 0 is elastic (E0)
    dgamma : work of adhesion Δγ (J/m²); 0 = adhesiveless (closure K = 0 at both edges)
    a0 : advance width of the edge energy balance (m); 0 = strict limit through the SIF
    modes : Chebyshev modes M (default from the relaxation length ℓ = v/ω_c: 4√(λ/ℓ), 64-512)
    quad : Gauss-Chebyshev / DCT nodes Q (default from ℓ)
    E_ref : modulus of the dimensionless groups (default the material's E0)
    """

    def __init__(self, material: Material, k: float, amplitude: float, velocity: float = 0.0,
                 dgamma: float = 0.0, a0: float = 0.0, modes: int | None = None,
                 quad: int | None = None, strip_nodes: int = 48, E_ref: float | None = None):
        self.material = material
        self.E_ref = material.E0 if E_ref is None else float(E_ref)
        self.k = float(k)
        self.lam = 2 * np.pi / self.k
        self.amp = float(amplitude)
        self.v = float(velocity)
        self.dgamma = float(dgamma)
        self.a0 = float(a0)
        self.kernel = Kernel1D(material, self.k, self.v)
        if modes is None:  # resolve the edge boundary layer of the relaxation length ℓ:
            modes = 64  # Chebyshev spacing at the edges ~ a(π/M)² ≪ ℓ
            if self.kernel.visco:
                modes = int(np.clip(32 * np.ceil(4 * np.sqrt(self.lam / self.kernel.scale) / 32),
                                    64, 512))
        self.M = int(modes)
        if quad is None:  # resolve the kernel's relaxation length v/ω_c across a period
            quad = 1024  # elastic: the smooth part log sinc(θ/2π) is analytic
            if self.kernel.visco:  # 0.5 λ/ℓ nodes (a fast DCT length), 2048 to 16384: with
                # 1024 the adhesiveless state's ẽ at ζ = 5e-3 was 3e-5 off (2048: 1e-7)
                need = np.clip(0.5 * self.lam / self.kernel.scale, 2048, 16384)
                quad = int(sfft.next_fast_len(int(np.ceil(need)), real=True))
        self.Q = int(quad)
        # the largest default mesh resolves the relaxation length ℓ down to λ/16384 (ζ ≈ 7e-4
        # in the seed's units): below, states converge slowly and less accurately, or not
        r = self.lam / self.kernel.scale if self.kernel.visco else 0.0
        self.underresolved = (
            f"the relaxation length ℓ = λ/{r:.3g} is below what the 1D mesh resolves (512 "
            "modes and 16384 kernel nodes at most: ℓ ≥ λ/16384, ζ ≳ 7e-4 for the seed's "
            "SLS); ζ = 0 is the elastic E0 limit it approaches where vτ ≪ a0"
            if r > 16384 else "")
        self.strip_nodes = strip_nodes
        self._shapes: dict[float, _Shape] = {}  # see :meth:`shape`
        self.Estar_tip = self.kernel.E_tip / (1 - material.nu**2)

    # -- profile ------------------------------------------------------------------------
    def w(self, x, delta):
        """Displacement prescribed in contact: Λ cos(kx) - Λ + Δ."""
        return self.amp * (np.cos(self.k * np.asarray(x)) - 1.0) + delta

    # -- one domain -----------------------------------------------------------------------
    def shape(self, a: float) -> _Shape:
        """What a contact domain's solution owes to its half-width a alone (cached).

        The kernel depends on x − x' only, so the response matrix of Eq. (15) at a domain's own
        collocation points depends on a, not on the centre c; and the prescribed displacement
        Λ(cos k(c + aξ) − 1) = Λ[cos kc (cos kaξ − 1) + (cos kc − 1) − sin kc sin kaξ] is a
        combination of three c-independent right-hand sides.  One build and one solve per a
        serve every centre and penetration: the eccentricity costs nothing, and the advanced
        domains of both edges (half-width a + a0/2) share one build.
        """
        key = float(a)
        sh = self._shapes.pop(key, None)
        if sh is None:
            dom = Domain.centred(key, 0.0, self.M, self.Q)
            A = dom.response(self.kernel, dom.x)
            kx = self.k * key * dom.xi
            rhs = np.column_stack([-2.0 * np.sin(0.5 * kx) ** 2, np.sin(kx), np.ones(self.M)])
            sh = _Shape(dom, np.linalg.solve(A, rhs))
        self._shapes[key] = sh  # most recent last
        while len(self._shapes) > 8:
            self._shapes.pop(next(iter(self._shapes)))
        return sh

    def pair_at(self, a: float, c: float):
        """Eq. (15) on the domain of half-width a centred at c for the two unit loadings:
        (domain, c_w, c_1), the state at penetration Δ having the Chebyshev coefficients
        c_w + Δ c_1 (the problem is linear in Δ)."""
        sh = self.shape(a)
        kc = self.k * c
        S = sh.sol
        cw = self.amp * (np.cos(kc) * S[:, 0] - 2.0 * np.sin(0.5 * kc) ** 2 * S[:, 2]
                         - np.sin(kc) * S[:, 1])
        return Domain.centred(sh.domain.a, c, self.M, self.Q), cw, S[:, 2].copy()

    def domain_pair(self, l1, l2):
        """:meth:`pair_at` for the domain [-l1, l2]."""
        return self.pair_at(0.5 * (l1 + l2), 0.5 * (l2 - l1))

    def advanced_pair(self, dom: Domain, side: int, a0: float):
        """:meth:`pair_at` for ``dom`` grown by a0 at edge ``side`` (1 trailing, 2 leading):
        both edges' advances share the half-width a + a0/2."""
        return self.pair_at(dom.a + 0.5 * a0, dom.c + (-0.5 if side == 1 else 0.5) * a0)

    def solve_domain(self, l1, l2, *, penetration=None, mean_pressure=None) -> State:
        """Solve Eq. (15) on [-l1, l2] at given Δ, or at given mean pressure p∞ (Δ solved)."""
        return self.state_of(self.domain_pair(l1, l2), penetration=penetration,
                             mean_pressure=mean_pressure)

    def state_of(self, pair, *, penetration=None, mean_pressure=None) -> State:
        """The state of a :meth:`pair_at` at given Δ or mean pressure p∞ (Δ solved)."""
        dom, cw, c1 = pair
        delta = penetration
        if delta is None:
            # p∞ = a π c0 / λ fixes Δ
            delta = (mean_pressure * self.lam / (dom.a * np.pi) - cw[0]) / c1[0]
        coef = cw + delta * c1
        pm = dom.a * np.pi * coef[0] / self.lam
        return State(dom, coef, float(delta), float(pm), dom.sif(coef))

    def edge_law(self, pair, side: int):
        """Edge ``side`` (1 trailing, 2 leading) of a domain as a function of Δ.

        Returns (K, work, gap): K(Δ) = k0 + k1 Δ (the SIF), the strip work δL(Δ) = q0 + q1 Δ +
        q2 Δ² of Eq. (8) (closing the strip of width a0 with the domain held) and the strip
        integral of the gap before closure s0 + s1 Δ, as coefficient arrays (lowest first).
        Both the gap g₋ and the advanced pressure p₊ are linear in Δ, so one solve of each
        domain serves every Δ.  ``work`` and ``gap`` are None when a0 = 0.
        """
        dom, cw, c1 = pair
        K = np.array([dom.sif(cw)[side - 1], dom.sif(c1)[side - 1]])
        if self.a0 == 0.0:
            return K, None, None
        adv, aw, a1 = self.advanced_pair(dom, side, self.a0)
        xs, ws, R = self._strip(dom, side, self.a0)
        g0 = R @ cw - self.amp * (np.cos(self.k * xs) - 1.0)
        g1 = R @ c1 - 1.0
        p0, p1 = adv.pressure(aw, xs), adv.pressure(a1, xs)
        work = -0.5 * np.array([np.sum(ws * g0 * p0), np.sum(ws * (g0 * p1 + g1 * p0)),
                                np.sum(ws * g1 * p1)])
        return K, work, np.array([np.sum(ws * g0), np.sum(ws * g1)])

    def edge_residual(self, law, delta: float, a: float) -> float:
        """The edge residual of :meth:`_residual` (√(G/Δγ) - 1, or the scaled SIF without
        adhesion) from an :meth:`edge_law` of a domain of half-width a at penetration Δ.

        Without adhesion the SIF is scaled by that of Westergaard's pressure on the same
        half-width, 2p*·sin(ka/2)·√(πa) (its peak pressure times √(πa)): the residual is then
        a relative edge position at any load (an absolute scale stopped the search with ẽ
        off by 1.5e-4 of ã at p̃ = 1e-9, ã = 2e-5, ζ = 0.1; now 1e-11)."""
        K, work, gap = law
        if self.dgamma == 0.0:
            scale = 2.0 * self.p_star() * np.sin(0.5 * self.k * a) * np.sqrt(np.pi * a)
            return float((K[0] + K[1] * delta) / scale)
        if work is None:
            k = K[0] + K[1] * delta
            g = k * abs(k) / (2 * self.Estar_tip)
        else:
            g = (np.sign(gap[0] + gap[1] * delta)
                 * abs(work[0] + work[1] * delta + work[2] * delta**2) / self.a0)
        return float(np.sign(g) * np.sqrt(abs(g) / self.dgamma) - 1.0)

    def edge_balance_delta(self, law) -> float:
        """The penetration Δ at which the edge of ``law`` balances (nan if none).

        δL(Δ) = a0 Δγ is a quadratic: of its roots the one with the edge in tension (the larger
        K) and an open gap before closure is the physical one; with a0 = 0, K = √(2E*Δγ);
        without adhesion K = 0."""
        K, work, gap = law
        if self.dgamma == 0.0 or work is None:
            target = 0.0 if self.dgamma == 0.0 else np.sqrt(2 * self.Estar_tip * self.dgamma)
            return float((target - K[0]) / K[1])
        q0, q1, q2 = work[0] - self.a0 * self.dgamma, work[1], work[2]
        disc = q1 * q1 - 4 * q2 * q0
        if not disc >= 0 or q2 == 0:
            return np.nan
        r = np.sqrt(disc)
        roots = [(-q1 + r) / (2 * q2), (-q1 - r) / (2 * q2)]
        roots = [d for d in roots if gap[0] + gap[1] * d > 0]
        if not roots:
            return np.nan
        return float(max(roots, key=lambda d: K[0] + K[1] * d))

    def interpenetration(self, state: State, n: int = 64) -> float:
        """-min(gap)/Λ over n points spread across the separated part of the period (> 0: the
        state interpenetrates outside its contact and is not admissible)."""
        x = state.l2 + (self.lam - state.l1 - state.l2) * (np.arange(n) + 0.5) / n
        return float(max(0.0, -np.min(self.gap(state, x)) / self.amp))

    def gap(self, state: State, x) -> np.ndarray:
        """g = u - w at points x (zero inside the contact up to the collocation error)."""
        A = state.domain.response(self.kernel, x)
        return A @ state.coef - self.w(x, state.penetration)

    # -- edge energy balance ------------------------------------------------------------
    def _strip_points(self, base, side: int, a0: float, beta: float):
        """Gauss-Jacobi nodes x and weights on the strip of width a0 outside edge ``side``
        (1 trailing, 2 leading), for integrands ~ (distance to new edge)^-½ ·
        (distance to old edge)^beta.  Returns (x, weights already divided by the weight)."""
        t, wq = roots_jacobi(self.strip_nodes, -0.5, beta)  # (1-t)^-½ (1+t)^beta
        # t = -1 at the old edge, t = +1 at the new edge
        off = base.a + a0 * (1 + t) / 2  # distance from the centre
        x = base.c + (-off if side == 1 else off)
        wfac = (1 - t) ** -0.5 * (1 + t) ** beta
        return x, (a0 / 2) * wq / wfac

    def _strip(self, base: Domain, side: int, a0: float):
        """(x, weights, response matrix) on the strip of width a0 outside edge ``side`` of
        ``base`` for g₋ p₊ ~ (old edge)^½ (new edge)^-½; the matrix depends on the half-width
        only and is cached with :meth:`shape`."""
        xs, ws = self._strip_points(base, side, a0, 0.5)
        sh = self.shape(base.a)
        key = (side, float(a0))
        if key not in sh.strips:
            sh.strips[key] = sh.domain.response(self.kernel, xs - base.c)
        return xs, ws, sh.strips[key]

    def edge_work(self, base: State, side: int, a0: float | None = None):
        """(advanced state, EdgeWork) for closing the strip of width a0 outside edge ``side``.

        δL = ½∫_strip g₋ t₊ (Eq. 8 restricted to the strip, where it is supported);
        δU = ½[∫p₊u₊ - ∫p₋u₋] (Eq. 9) and δL_P = ½[∫u₊p₋ - ∫u₋p₊] (Eq. 10), each from its
        own quadrature, so δL = δU + δL_P (Eq. 6) is a check of the discrete solution.
        """
        a0 = self.a0 if a0 is None else a0
        l1, l2 = base.l1, base.l2
        adv = self.state_of(self.advanced_pair(base.domain, side, a0), penetration=base.penetration)
        xs, ws, R = self._strip(base.domain, side, a0)  # for g₋ p₊ ~ (old)^½ (new)^-½
        g_minus = R @ base.coef - self.w(xs, base.penetration)
        gap_sign = float(np.sign(np.sum(ws * g_minus)))
        dL = -0.5 * float(np.sum(ws * g_minus * adv.domain.pressure(adv.coef, xs)))
        bd, ad = base.domain, adv.domain

        def w_of(x):
            return self.w(x, base.penetration)

        strip = (-l1 - a0, -l1) if side == 1 else (l2, l2 + a0)
        int_w_pplus_strip = ad.integrate_range(adv.coef, w_of, *strip)
        int_w_pplus_base = ad.integrate_range(adv.coef, w_of, -l1, l2)
        w_b = self.w(bd.xq, base.penetration)
        int_pp_up = ad.integrate(adv.coef, self.w(ad.xq, base.penetration))  # ∫ p₊ u₊ (u₊ = w)
        int_pm_um = bd.integrate(base.coef, w_b)  # ∫ p₋ u₋
        # ∫ u₋ p₊ = ∫_{A₋} w p₊ + ∫_strip (w + g₋) p₊ ;  ∫ u₊ p₋ = ∫_{A₋} w p₋
        int_um_pp = int_w_pplus_base + int_w_pplus_strip - 2.0 * dL
        dU = 0.5 * (int_pp_up - int_pm_um)
        dLP = 0.5 * (int_pm_um - int_um_pp)
        return adv, EdgeWork(dL, dU, dLP, gap_sign)

    def release_rates(self, state: State):
        """Signed (δL1/a0, δL2/a0), or for a0 = 0 K_i|K_i|/(2E_tip*) (J/m²).

        The sign is that of the gap before closure (a compressive edge, K < 0, interpenetrates
        just outside and is not an admissible state), so only admissible states balance Δγ.
        """
        if self.a0 == 0.0:
            return tuple(K * abs(K) / (2 * self.Estar_tip) for K in state.K)
        works = []
        for side in (1, 2):
            _, ew = self.edge_work(state, side)
            works.append(ew)
        state.work = tuple(works)
        return tuple(ew.gap_sign * abs(ew.dL) / self.a0 for ew in works)

    # -- equilibrium --------------------------------------------------------------------
    def _residual(self, y, control, value):
        """Edge residuals (trailing, leading) of the domain of half-width a centred at c,
        y = (a, c), at given Δ or p∞."""
        a, c = y
        if not (a > 0 and 2 * a < self.lam * 0.999):
            return np.array([1e3, 1e3])
        pair = self.pair_at(a, c)
        dom, cw, c1 = pair
        delta = (value if control == "penetration"
                 else (value * self.lam / (dom.a * np.pi) - cw[0]) / c1[0])
        return np.array([self.edge_residual(self.edge_law(pair, side), delta, a)
                         for side in (1, 2)])

    def p_star(self):
        """p* = E0* k Λ/2 (Westergaard full-contact pressure), with E0 = ``E_ref``."""
        return self.E_ref / (1 - self.material.nu**2) * self.k * self.amp / 2

    def equilibrium(self, *, penetration=None, mean_pressure=None, guess=None, tol=1e-11, ftol=1e-8,
                    fatol=1e-10):
        """Partial-contact equilibrium at given Δ or p∞ from a guess (l1, l2).

        A state whose surface crosses the rigid profile outside the contact (by more than
        1e-6 Λ at 64 points of the separated part) is not an equilibrium: not converged, with
        the reason in ``info.message`` (:meth:`robust_equilibrium` then tries the next
        guess).

        Converged when both edge residuals ``√(δL_i/(a0 Δγ)) - 1`` (or the SIF residuals) are
        below ``ftol`` — MINPACK's own flag is not used, since at tiny a0 the residual has a
        noise floor of ~1e-10 that stops its step-size test, not the balance.  The search
        stops as soon as both residuals are below ``fatol`` (the edges then sit within
        ~fatol/k of the balance; MINPACK's step test alone took as many evaluations again
        at the residuals' round-off level, measured at ζ = 1e-3), or at its step size ``tol``.
        """
        control, value = one_control(mean_pressure, penetration)
        if guess is None:
            guess = self.elastic_guess(control, value)
        l1, l2 = np.asarray(guess, float)
        count = [0]

        def fun(y):
            r = self._residual(y, control, value)
            count[0] += 1
            if np.all(np.abs(r) < fatol):
                raise _Balanced(np.array(y, float), r)
            return r

        # unknowns (a, c): a step in the eccentricity alone reuses the cached shape
        try:
            sol = root(fun, np.array([0.5 * (l1 + l2), 0.5 * (l2 - l1)]), method="hybr",
                       options={"xtol": tol})
            x, f, message = sol.x, sol.fun, sol.message
        except _Balanced as done:
            x, f, message = done.x, done.fun, f"both edge residuals below {fatol:g}"
        a, c = x
        ok = bool(np.all(np.abs(f) < ftol))
        if not ok:  # MINPACK's "The solution converged." is about its step size only
            why = " ".join(str(message).split())
            why = "its step-size test was met" if why == "The solution converged." else why
            message = (f"not converged: edge residuals up to {np.max(np.abs(f)):.1e}, above "
                       f"the tolerance {ftol:g} (root finder: {why})")
        if not (a > 0 and 2 * a < 0.999 * self.lam):  # left the admissible half-widths
            message = (f"not converged: the root finder left the admissible half-widths "
                       f"(ka = {self.k * a:.3g})")
            a, c = 0.5 * (l1 + l2), 0.5 * (l2 - l1)
        st = self.state_of(self.pair_at(a, c), **{control: value})
        if self.dgamma and self.a0:
            self.release_rates(st)
        over = self.interpenetration(st) if ok else 0.0
        if over > 1e-6:  # both edges balance, but the surface crosses the profile elsewhere
            ok = False
            message = f"inadmissible: interpenetrates by {over:.1e} Λ outside the contact"
        st.info = SolveInfo(ok, message, count[0], float(np.max(np.abs(f))), tuple(f),
                            (control, value), over)
        return st

    def guesses(self, control, value):
        """Starting edges to try: symmetric elastic contacts with E0, |E(kv)| and E∞."""
        out = [self.elastic_guess(control, value)]
        if self.kernel.visco:
            for E in (abs(self.material.modulus(np.array([self.k * self.v]))[0]),
                      self.material.Einf):
                out.append(self.elastic_guess(control, value, E))
        return out

    def robust_equilibrium(self, *, penetration=None, mean_pressure=None, guess=None):
        """:meth:`equilibrium` from ``guess``, then from each of :meth:`guesses`.

        With adhesion the load (or Δ) may have several equilibria: a converged state on the
        falling branch (:func:`branch_slope` ≤ 0, beyond the snap-in maximum: unstable) is
        kept only if no guess reaches the rising branch — measured: the ζ sweep at p̃∞ = 0.15
        continued from ζ = 0.3 (ã = 1.37) reached ã = 2.19 at ζ = 1, where dp̃/dã < 0, while
        the elastic guess gives the rising ã = 0.90.  ``info.branch_slope`` is reported.
        """
        control, value = one_control(mean_pressure, penetration)
        st = falling = None
        tried = []
        for g in ([guess] if guess is not None else []) + self.guesses(control, value):
            g = np.asarray(g, dtype=float)
            if any(np.allclose(g, t, rtol=1e-9, atol=0) for t in tried):
                continue  # the same start again (e.g. |E(kv)| ≈ E0 at small ζ) would fail again
            tried.append(g)
            st = self.equilibrium(guess=g, **{control: value})
            if not st.info.converged:
                continue
            from .branches import branch_slope  # the branch is traced on this problem

            st.info.branch_slope = (branch_slope(self, st, control) if self.dgamma > 0
                                       else np.inf)  # without adhesion p(a) only rises
            if not st.info.branch_slope <= 0:
                return st
            falling = falling or st
        return falling or st

    def elastic_guess(self, control, value, E=None):
        """Symmetric Johnson (1995) contact with modulus E (default E0) at the same load."""
        from .. import reference as ref

        beta = (self.material.E0 if E is None else E) / self.E_ref
        Gam = (1 - self.material.nu**2) * self.dgamma / (np.pi * self.E_ref * self.k
                                                         * self.amp**2)
        if control == "mean_pressure":
            pt = value / self.p_star()
            a = (ref.johnson_a(pt, Gam, beta) if Gam > 0
                 else ref.westergaard_a(pt / beta))
            if not np.isfinite(a):
                a = 1.0
        else:
            a = 1.0
        return (a / self.k, a / self.k)

    # -- outputs ------------------------------------------------------------------------
    def fourier_coefficients(self, state: State, n) -> np.ndarray:
        """p_n = ∫ p e^{-i n k x} dx, exactly: the basis T_m(ξ)/√(1-ξ²) transforms to
        π (-i)^m J_m(n k a)."""
        from scipy.special import jv

        d = state.domain
        n = np.asarray(n, dtype=float)
        m = np.arange(self.M)
        z = n * self.k * d.a
        series = np.zeros(n.shape, dtype=complex)
        for mm in m:  # loop over the few modes, vectorised over n
            series += state.coef[mm] * (-1j) ** mm * jv(mm, z)
        return d.a * np.pi * np.exp(-1j * n * self.k * d.c) * series

    def friction_dissipation(self, state: State, nmax: int = 200_000) -> float:
        """μ from the dissipation, docs/derivations.md §5 in 1D:
        μ = 4(1-ν²)/(λ² p∞) Σ_{n>0} |p_n|² Im[1/E(nkv)].

        The sum is taken to ``nmax`` and its tail added from the edge asymptote
        |p_n|² → (K1² + K2²)/(2 n k) with Im[1/E] → α/(n k v).
        """
        if not self.kernel.visco:
            return 0.0
        n = np.arange(1, nmax + 1)
        pn = self.fourier_coefficients(state, n)
        imJ = np.imag(self.kernel.compliance(n))
        total = np.sum(np.abs(pn) ** 2 * imJ)
        K1, K2 = state.K
        total += (K1**2 + K2**2) * self.kernel.alpha / (2 * self.k**2 * self.v) / (nmax + 0.5)
        return float(4 * (1 - self.material.nu**2) / (self.lam**2 * state.mean_pressure) * total)

    def friction(self, state: State):
        """μ of Eq. (19): -(1/(λ p∞)) ∫ p u' dx with u' = w' = -Λk sin(kx) on the contact.

        Undefined (nan) at exactly zero mean pressure; see :meth:`friction_force`."""
        if state.mean_pressure == 0.0:
            return np.nan
        return self.friction_force(state) / (self.lam * state.mean_pressure)

    def friction_force(self, state: State) -> float:
        """Tangential force per unit length and period, -∫ p u' dx (N/m)."""
        d = state.domain
        up = -self.amp * self.k * np.sin(self.k * d.xq)
        return -d.integrate(state.coef, up)
