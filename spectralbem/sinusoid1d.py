"""The seed's 1D method (Section 3): adhesive viscoelastic sliding of a rigid sinusoid
h = Λ cos(kx) on a half-plane, with continuous contact edges.

Discretisation (spectral, on the contact domain [-l1, l2] only)
    The pressure is ``p(x) = Σ_m c_m T_m(ξ)/√(1-ξ²)``, x = c + aξ, c = (l2-l1)/2,
    a = (l1+l2)/2: the square-root edge singularity of adhesive contact is built in, and the
    stress-intensity factors follow from the coefficients.  Eq. (15) is collocated at the
    Chebyshev roots.

Kernel (seed Eq. (13) / (A.18), with p = -σ so that u = ∫ C p)
    ``C(x) = -(2(1-ν²)/(π E_ref)) log|2 sin(kx/2)| + R(x)`` with E_ref = E∞ for a viscoelastic
    material (the glassy log singularity of Eq. 13: J(0) = 1/E∞) and E_ref = E for an elastic
    one (R = 0).  ``log|2 sin(θ/2)| = log|θ| + log sinc(θ/2π)``: the first term is integrated
    exactly against the basis (∫ log|ξ-σ| T_m(σ)/√(1-σ²) dσ = -(π/m) T_m(ξ)), the rest is
    smooth.  R has Fourier coefficients ``2(1-ν²)(1/E(nkv) - 1/E∞)/(|n|k)``: its 1/n² tail is
    summed in closed form (Clausen function Cl2), the converging rest is tabulated by FFT.  The
    smooth part is integrated against all basis functions at once by a DCT in φ (σ = cos φ).

Edge energy balance (Eqs. 3, 7-10, 16-17, 20-21) with an explicit advance width a0
    δL_i is the work of Eq. (8) of closing the strip of width a0 just outside edge i at fixed Δ
    (the other edge fixed): ``δL = ½∫_strip g₋ t₊ dx`` with the gap g₋ before and the tensile
    stress t₊ = -p₊ after closure (physics.md §0.2 item 2), integrated by Gauss-Jacobi
    quadrature that carries the √ end behaviours.  Equilibrium: δL_i/a0 = Δγ at both edges.
    δU (Eq. 9) and δL_P (Eq. 10) are computed on the same perturbation; G_i = δU_i/a0, which
    at equilibrium is Eq. (20)/(21).  a0 = 0 selects the strict limit through the SIF:
    δL/δl = K²/(2 E_tip*) with E_tip = E∞ (glassy tip) for a viscoelastic material.

Units follow :mod:`spectralbem.conventions`; :func:`solve` is the dimensionless entry point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft
from scipy.optimize import root
from scipy.special import bernoulli, roots_jacobi

from .materials import Elastic, Material, StandardLinearSolid

# ---------------------------------------------------------------------------------------------
# special functions

_K = np.arange(1, 35)
_CL2 = np.abs(bernoulli(80)[2 * _K]) / (2 * _K * (2 * _K + 1)
                                       * np.array([math.factorial(2 * k) for k in _K], float))


def clausen2(theta) -> np.ndarray:
    """Cl2(θ) = Σ sin(nθ)/n² = -∫₀^θ log|2 sin(t/2)| dt (series on (-π, π], 1e-14 absolute)."""
    r = np.mod(np.asarray(theta, dtype=float) + np.pi, 2 * np.pi) - np.pi
    out = np.zeros_like(r)
    nz = r != 0
    x = r[nz]
    x2 = x * x
    acc = np.zeros_like(x)
    pw = x * x2
    for cf in _CL2:
        acc += cf * pw
        pw *= x2
    out[nz] = x - x * np.log(np.abs(x)) + acc
    return out


def log_sinc(theta) -> np.ndarray:
    """log(2 sin(θ/2)/θ) for |θ| < 2π (analytic; -inf at ±2π)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.log(np.sinc(np.asarray(theta) / (2 * np.pi)))


# ---------------------------------------------------------------------------------------------
# periodic kernel


class Kernel1D:
    """The 1D periodic kernel C(x) of Eq. (13)/(A.18) for a material sliding at speed v."""

    def __init__(self, material: Material, k: float, v: float, table_size: int | None = None):
        self.material = material
        self.k = float(k)
        self.lam = 2 * np.pi / self.k
        self.v = float(v)
        self.f = 2.0 * (1.0 - material.nu**2)
        self.visco = (not material.is_elastic) and self.v != 0.0
        self.E_tip = material.Einf if self.visco else material.E0
        self.cL = self.f / (np.pi * self.E_tip)
        self.table = None
        if self.visco:
            self._build_table(table_size)

    def compliance(self, n) -> np.ndarray:
        """1/E(n k v) for integer wavenumbers n."""
        if not self.visco:
            return np.full(np.shape(n), 1.0 / self.material.E0, dtype=complex)
        return self.material.compliance(np.asarray(n, float) * self.k * self.v)

    def _build_table(self, size):
        mat, k, v = self.material, self.k, self.v
        Jinf = 1.0 / mat.Einf
        dJ = 1.0 / mat.E0 - Jinf
        # wavenumber where 1/E(nkv) has relaxed half-way toward 1/E∞
        w = np.logspace(-12, 12, 2401)
        D = np.abs(mat.compliance(w) - Jinf)
        wc = w[np.argmax(D < 0.5 * dJ)] if np.any(D < 0.5 * dJ) else w[-1]
        nc = max(wc / (k * abs(v)), 1.0)
        self.scale = abs(v) / wc  # relaxation length of the kernel (m)
        if size is None:
            size = int(2 ** np.clip(np.ceil(np.log2(200 * nc)), 12, 20))
        self.table_size = size
        whi = 1e7 * max(wc, size * k * abs(v))
        self.alpha = float(whi * np.imag(mat.compliance(np.array([whi]))[0]))  # Im D ~ α/ω
        n = np.arange(1, size // 2)
        Rn = self.f * (mat.compliance(n * k * v) - Jinf - 1j * self.alpha / (n * k * v)) / (n * k)
        spec = np.zeros(size, dtype=complex)
        spec[1: size // 2] = Rn
        spec[size - n] = np.conj(Rn)
        self.dx = self.lam / size
        self.nodes = np.arange(size) * self.dx
        # converging part by FFT + the α/ω tail summed exactly: -(2fα/(λk²v)) Cl2(kx)
        tail = -2.0 * self.f * self.alpha / (self.lam * k**2 * v)
        self.table = (size / self.lam) * np.fft.ifft(spec).real + tail * clausen2(k * self.nodes)

    def remainder(self, d) -> np.ndarray:
        """R(d): the viscoelastic part of the kernel (zero for elastic)."""
        d = np.asarray(d, dtype=float)
        if self.table is None:
            return np.zeros_like(d)
        return np.interp(d, self.nodes, self.table, period=self.lam)

    def smooth(self, d) -> np.ndarray:
        """C(d) minus its log|k d| singularity, for |d| < λ."""
        return -self.cL * log_sinc(self.k * d) + self.remainder(d)

    def spectrum(self, n) -> np.ndarray:
        """Ĉ_n = 2(1-ν²)/(|n| k E(nkv)) (n ≠ 0)."""
        n = np.asarray(n, float)
        return self.f * self.compliance(n) / (np.abs(n) * self.k)


# ---------------------------------------------------------------------------------------------
# one contact domain


def _log_moments(xi: np.ndarray, M: int) -> np.ndarray:
    """L_m(ξ) = ∫_{-1}^{1} log|ξ-σ| T_m(σ)/√(1-σ²) dσ for any real ξ (columns m = 0..M-1)."""
    xi = np.asarray(xi, dtype=float)
    out = np.empty((xi.size, M))
    inside = np.abs(xi) <= 1
    m = np.arange(1, M)
    xin = xi[inside]
    out[inside, 0] = -np.pi * np.log(2.0)
    out[inside, 1:] = -(np.pi / m) * np.cos(m * np.arccos(xin)[:, None])
    xo = xi[~inside]
    if xo.size:
        root_ = np.sqrt(xo * xo - 1.0)
        out[~inside, 0] = np.pi * np.log((np.abs(xo) + root_) / 2.0)
        z = xo - np.sign(xo) * root_
        out[~inside, 1:] = -(np.pi / m) * z[:, None] ** m
    return out


@dataclass
class Domain:
    """Contact domain [-l1, l2] with its spectral discretisation."""

    l1: float
    l2: float
    M: int
    Q: int

    def __post_init__(self):
        self.c = 0.5 * (self.l2 - self.l1)
        self.a = 0.5 * (self.l1 + self.l2)
        j = np.arange(1, self.M + 1)
        self.xi = np.cos((2 * j - 1) * np.pi / (2 * self.M))
        self.x = self.c + self.a * self.xi
        self.phi = (np.arange(self.Q) + 0.5) * np.pi / self.Q
        self.xq = self.c + self.a * np.cos(self.phi)  # Gauss-Chebyshev nodes
        self.Tq = np.cos(np.arange(self.M)[:, None] * self.phi[None, :])  # (M, Q)

    def response(self, kernel: Kernel1D, x) -> np.ndarray:
        """Matrix A with u(x) = A @ c for points x (any position within a period)."""
        x = np.asarray(x, dtype=float)
        lam = kernel.lam
        x = self.c + np.mod(x - self.c + lam / 2, lam) - lam / 2  # nearest periodic image
        xi = (x - self.c) / self.a
        A = _log_moments(xi, self.M)
        A[:, 0] += np.pi * (np.log(self.a) + np.log(kernel.k))
        A *= -kernel.cL * self.a
        F = kernel.smooth(x[:, None] - self.xq[None, :])
        Y = sfft.dct(F, type=2, axis=1)[:, : self.M]
        A += self.a * (np.pi / self.Q) * 0.5 * Y
        return A

    def pressure(self, coef, x) -> np.ndarray:
        xi = (np.asarray(x, float) - self.c) / self.a
        inside = np.abs(xi) < 1
        out = np.zeros_like(xi)
        T = np.cos(np.arange(self.M)[None, :] * np.arccos(np.clip(xi[inside], -1, 1))[:, None])
        out[inside] = (T @ coef) / np.sqrt(1 - xi[inside] ** 2)
        return out

    def integrate(self, coef, values) -> float:
        """∫ p f dx over the contact, f given at the Gauss-Chebyshev nodes ``self.xq``."""
        return float(self.a * (np.pi / self.Q) * np.dot(coef @ self.Tq, values))

    def integrate_range(self, coef, f, x_lo: float, x_hi: float, n: int | None = None) -> float:
        """∫_{x_lo}^{x_hi} p f dx over a sub-range of the contact, f smooth.

        In the angle variable (x = c + a cos φ) ``p dx = a Σ c_m cos(mφ) dφ`` is smooth, so
        Gauss-Legendre in φ is spectrally accurate whatever the edge singularities.
        """
        n = n or self.M + 48
        lo = np.arccos(np.clip((x_hi - self.c) / self.a, -1, 1))
        hi = np.arccos(np.clip((x_lo - self.c) / self.a, -1, 1))
        t, wt = np.polynomial.legendre.leggauss(n)
        phi = 0.5 * (hi + lo) + 0.5 * (hi - lo) * t
        x = self.c + self.a * np.cos(phi)
        series = np.cos(phi[:, None] * np.arange(self.M)[None, :]) @ coef
        return float(self.a * 0.5 * (hi - lo) * np.sum(wt * f(x) * series))

    def sif(self, coef):
        """Tensile stress-intensity factors (K1 trailing at -l1, K2 leading at +l2)."""
        sgn = (-1.0) ** np.arange(self.M)
        s = np.sqrt(np.pi * self.a)
        return -float(np.dot(coef, sgn)) * s, -float(np.sum(coef)) * s


# ---------------------------------------------------------------------------------------------
# the problem


@dataclass
class EdgeWork:
    dL: float  # Eq. (8): work of closing the strip (J/m per unit length)
    dU: float  # Eq. (9)
    dLP: float  # Eq. (10)
    gap_sign: float = 1.0  # sign of ∫ g₋ on the strip: -1 means the base state interpenetrates


@dataclass
class State:
    domain: Domain
    coef: np.ndarray
    delta: float
    p_mean: float
    K: tuple
    work: tuple = (None, None)
    info: dict = field(default_factory=dict)

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
    modes : Chebyshev modes M; quad : Gauss-Chebyshev / DCT nodes Q (default from v τ / a)
    """

    def __init__(self, material: Material, k: float, amplitude: float, velocity: float = 0.0,
                 dgamma: float = 0.0, a0: float = 0.0, modes: int = 64, quad: int | None = None,
                 strip_nodes: int = 48):
        self.material = material
        self.k = float(k)
        self.lam = 2 * np.pi / self.k
        self.amp = float(amplitude)
        self.v = float(velocity)
        self.dgamma = float(dgamma)
        self.a0 = float(a0)
        self.M = int(modes)
        self.kernel = Kernel1D(material, self.k, self.v)
        if quad is None:  # resolve the kernel's relaxation length v/ω_c across a period
            quad = 4096
            if self.kernel.visco:
                quad = int(2 ** np.clip(np.ceil(np.log2(0.5 * self.lam / self.kernel.scale)),
                                        12, 14))
        self.Q = int(quad)
        self.strip_nodes = strip_nodes
        self.Estar_tip = self.kernel.E_tip / (1 - material.nu**2)

    # -- profile ------------------------------------------------------------------------
    def w(self, x, delta):
        """Displacement prescribed in contact: Λ cos(kx) - Λ + Δ."""
        return self.amp * (np.cos(self.k * np.asarray(x)) - 1.0) + delta

    # -- one domain -----------------------------------------------------------------------
    def solve_domain(self, l1, l2, *, delta=None, p_mean=None) -> State:
        """Solve Eq. (15) on [-l1, l2] at given Δ, or at given mean pressure p∞ (Δ solved)."""
        dom = Domain(l1, l2, self.M, self.Q)
        A = dom.response(self.kernel, dom.x)
        lu = np.linalg.solve
        rhs = np.column_stack([self.amp * (np.cos(self.k * dom.x) - 1.0), np.ones(self.M)])
        sol = lu(A, rhs)
        if delta is None:
            # p∞ = a π c0 / λ fixes Δ
            c0w, c01 = sol[0, 0], sol[0, 1]
            delta = (p_mean * self.lam / (dom.a * np.pi) - c0w) / c01
        coef = sol[:, 0] + delta * sol[:, 1]
        pm = dom.a * np.pi * coef[0] / self.lam
        return State(dom, coef, float(delta), float(pm), dom.sif(coef))

    def gap(self, state: State, x) -> np.ndarray:
        """g = u - w at points x (zero inside the contact up to the collocation error)."""
        A = state.domain.response(self.kernel, x)
        return A @ state.coef - self.w(x, state.delta)

    # -- edge energy balance ------------------------------------------------------------
    def _strip_points(self, base: State, side: int, a0: float, beta: float):
        """Gauss-Jacobi nodes x and weights on the strip of width a0 outside edge ``side``
        (1 trailing, 2 leading), for integrands ~ (distance to new edge)^-½ ·
        (distance to old edge)^beta.  Returns (x, weights already divided by the weight)."""
        t, wq = roots_jacobi(self.strip_nodes, -0.5, beta)  # (1-t)^-½ (1+t)^beta
        # t = -1 at the old edge, t = +1 at the new edge
        x = (-base.l1 - a0 * (1 + t) / 2) if side == 1 else (base.l2 + a0 * (1 + t) / 2)
        wfac = (1 - t) ** -0.5 * (1 + t) ** beta
        return x, (a0 / 2) * wq / wfac

    def edge_work(self, base: State, side: int, a0: float | None = None):
        """(advanced state, EdgeWork) for closing the strip of width a0 outside edge ``side``.

        δL = ½∫_strip g₋ t₊ (Eq. 8 restricted to the strip, where it is supported);
        δU = ½[∫p₊u₊ - ∫p₋u₋] (Eq. 9) and δL_P = ½[∫u₊p₋ - ∫u₋p₊] (Eq. 10), each from its
        own quadrature, so δL = δU + δL_P (Eq. 6) is a check of the discrete solution.
        """
        a0 = self.a0 if a0 is None else a0
        l1, l2 = base.l1, base.l2
        adv = (self.solve_domain(l1 + a0, l2, delta=base.delta) if side == 1
               else self.solve_domain(l1, l2 + a0, delta=base.delta))
        xs, ws = self._strip_points(base, side, a0, 0.5)  # for g₋ p₊ ~ (old)^½ (new)^-½
        g_minus = self.gap(base, xs)
        gap_sign = float(np.sign(np.sum(ws * g_minus)))
        dL = -0.5 * float(np.sum(ws * g_minus * adv.domain.pressure(adv.coef, xs)))
        bd, ad = base.domain, adv.domain

        def w_of(x):
            return self.w(x, base.delta)

        strip = (-l1 - a0, -l1) if side == 1 else (l2, l2 + a0)
        int_w_pplus_strip = ad.integrate_range(adv.coef, w_of, *strip)
        int_w_pplus_base = ad.integrate_range(adv.coef, w_of, -l1, l2)
        w_b = self.w(bd.xq, base.delta)
        int_pp_up = ad.integrate(adv.coef, self.w(ad.xq, base.delta))  # ∫ p₊ u₊ (u₊ = w)
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
        l1, l2 = y
        if not (l1 + l2 > 0 and l1 + l2 < self.lam * 0.999):
            return np.array([1e3, 1e3])
        st = self.solve_domain(l1, l2, **{control: value})
        if self.dgamma == 0.0:
            s = self.p_star() * np.sqrt(self.lam)
            return np.array([st.K[0] / s, st.K[1] / s])
        G = self.release_rates(st)
        return np.array([np.sign(g) * np.sqrt(abs(g) / self.dgamma) - 1.0 for g in G])

    def p_star(self):
        """p* = E0* k Λ/2 (Westergaard full-contact pressure)."""
        return self.material.E0 / (1 - self.material.nu**2) * self.k * self.amp / 2

    def equilibrium(self, *, delta=None, p_mean=None, guess=None, tol=1e-12):
        """Partial-contact equilibrium at given Δ or p∞ from a guess (l1, l2)."""
        control, value = ("delta", delta) if delta is not None else ("p_mean", p_mean)
        if guess is None:
            guess = self.elastic_guess(control, value)
        sol = root(self._residual, np.asarray(guess, float), args=(control, value),
                   method="hybr", options={"xtol": tol})
        l1, l2 = sol.x
        ok = bool(sol.success) and np.all(np.abs(sol.fun) < 1e-8)
        st = self.solve_domain(l1, l2, **{control: value})
        if self.dgamma and self.a0:
            self.release_rates(st)
        st.info = {"converged": ok, "message": sol.message, "nfev": sol.nfev,
                   "residual": float(np.max(np.abs(sol.fun)))}
        return st

    def elastic_guess(self, control, value):
        """Symmetric Johnson (1995) contact with E0 at the same load (or a small contact)."""
        from . import reference as ref

        Gam = (1 - self.material.nu**2) * self.dgamma / (np.pi * self.material.E0 * self.k
                                                         * self.amp**2)
        if control == "p_mean":
            pt = value / self.p_star()
            a = ref.johnson_a(pt, Gam) if Gam > 0 else ref.westergaard_a(pt)
            if not np.isfinite(a):
                a = 1.0
        else:
            a = 1.0
        return (a / self.k, a / self.k)

    # -- outputs ------------------------------------------------------------------------
    def friction(self, state: State):
        """μ of Eq. (19): -(1/(λ p∞)) ∫ p u' dx with u' = w' = -Λk sin(kx) on the contact."""
        d = state.domain
        up = -self.amp * self.k * np.sin(self.k * d.xq)
        return -d.integrate(state.coef, up) / (self.lam * state.p_mean)
