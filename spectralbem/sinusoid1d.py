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
    smooth.  R has Fourier coefficients ``2(1-ν²)(1/E(nkv) - 1/E∞)/(|n|k)``: its 1/n² and
    1/n³ tails are summed in closed form (Clausen functions Cl2, Cl3), the rest is tabulated by
    FFT and interpolated, with the Clausen kinks at the origin evaluated exactly.  The
    smooth part is integrated against all basis functions at once by a DCT in φ (σ = cos φ).

Edge energy balance (Eqs. 3, 7-10, 16-17, 20-21) with an explicit advance width a0
    δL_i is the work of Eq. (8) of closing the strip of width a0 just outside edge i at fixed Δ
    (the other edge fixed): ``δL = ½∫_strip g₋ t₊ dx`` with the gap g₋ before and the tensile
    stress t₊ = -p₊ after closure (docs/derivations.md §3), integrated by Gauss-Jacobi
    quadrature that carries the √ end behaviours.  Equilibrium: δL_i/a0 = Δγ at both edges.
    δU (Eq. 9) and δL_P (Eq. 10) are computed on the same perturbation; G_i = δU_i/a0, which
    at equilibrium is Eq. (20)/(21).  a0 = 0 selects the strict limit through the SIF:
    δL/δl = K²/(2 E_tip*) with E_tip = E∞ (glassy tip) for a viscoelastic material.

Units follow :mod:`spectralbem.conventions`; :func:`solve` is the dimensionless entry point.
"""

from __future__ import annotations

import functools
import math
import warnings
from dataclasses import dataclass, field

import numpy as np
import scipy.fft as sfft
from scipy.optimize import root
from scipy.special import bernoulli, roots_jacobi

from . import kernels
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


_ZETA3 = 1.2020569031595942


def clausen3(theta) -> np.ndarray:
    """Cl3(θ) = Σ cos(nθ)/n³ = ζ(3) - ∫₀^θ Cl2 (series on (-π, π], 1e-14 absolute)."""
    r = np.mod(np.asarray(theta, dtype=float) + np.pi, 2 * np.pi) - np.pi
    r2 = r * r
    out = _ZETA3 - 0.75 * r2
    nz = r != 0
    out[nz] += 0.5 * r2[nz] * np.log(np.abs(r[nz]))
    pw = r2 * r2
    for kk, cf in zip(_K, _CL2, strict=True):
        out -= cf * pw / (2 * kk + 2)
        pw = pw * r2
    return out


def log_sinc(theta) -> np.ndarray:
    """log(2 sin(θ/2)/θ) for |θ| < 2π (analytic; -inf at ±2π)."""
    h = 0.5 * np.asarray(theta, dtype=float)
    r = np.sin(h)
    np.divide(r, h, out=r, where=h != 0)
    r[h == 0] = 1.0
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.log(r, out=r)


@functools.lru_cache(maxsize=16)
def _leggauss(n: int):
    return np.polynomial.legendre.leggauss(n)


def _hermite(vals, slopes, pos, dx, periodic=False):
    """Cubic Hermite interpolation on a uniform grid; ``pos`` in units of the spacing."""
    i0 = np.floor(pos).astype(np.intp)
    t = pos - i0
    n = vals.size
    if periodic:
        i0 %= n
        i1 = i0 + 1
        i1[i1 == n] = 0
    else:
        i0 = np.clip(i0, 0, n - 2)
        t = pos - i0
        i1 = i0 + 1
    t2 = t * t
    tm1 = t - 1.0
    return ((1 + 2 * t) * tm1 * tm1 * vals[i0] + t2 * (3 - 2 * t) * vals[i1]
            + dx * (t * tm1 * tm1 * slopes[i0] + t2 * tm1 * slopes[i1]))


def _periodic_cubic(vals, slopes, dx):
    """Power-form coefficients of the periodic cubic Hermite interpolant, one row
    (c0, c1, c2, c3) per interval: on [i, i+1), value = c0 + t(c1 + t(c2 + t c3))."""
    v1, s0 = np.roll(vals, -1), dx * slopes
    s1 = np.roll(s0, -1)
    return np.ascontiguousarray(np.stack(
        [vals, s0, 3.0 * (v1 - vals) - 2.0 * s0 - s1, 2.0 * (vals - v1) + s0 + s1], axis=1))


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
            size = int(2 ** np.clip(np.ceil(np.log2(64 * nc)), 12, 20))
        self.table_size = size
        whi = 1e7 * max(wc, size * k * abs(v))
        Dhi = mat.compliance(np.array([whi]))[0] - Jinf
        self.alpha = float(whi * Dhi.imag)  # Im D ~ α/ω (no cancellation in Im)
        # Re D ~ β2/ω²: estimated where the asymptote holds but Re(1/E) - 1/E∞ is still
        # resolved in float64 (100× beyond |D| = 1e-4 ΔJ)
        small = D < 1e-4 * dJ
        w2 = 100 * (w[np.argmax(small)] if np.any(small) else w[-1])
        self.beta2 = float(w2**2 * (mat.compliance(np.array([w2]))[0] - Jinf).real)
        n = np.arange(1, size // 2)
        w_n = n * k * v
        Dn = mat.compliance(w_n) - Jinf - 1j * self.alpha / w_n - self.beta2 / w_n**2
        Rn = self.f * Dn / (n * k)
        spec = np.zeros(size, dtype=complex)
        spec[1: size // 2] = Rn
        spec[size - n] = np.conj(Rn)
        self.dx = self.lam / size
        self.nodes = np.arange(size) * self.dx
        # the asymptotic tails summed exactly: α/ω → Cl2, β2/ω² → Cl3
        self.tail2 = -2.0 * self.f * self.alpha / (self.lam * k**2 * v)
        self.tail3 = 2.0 * self.f * self.beta2 / (self.lam * k**3 * v**2)
        # converging part: values and slopes for cubic Hermite interpolation (it varies on
        # the relaxation length v/ω_c, so linear interpolation would cost (δ/ℓ)²)
        freq = np.fft.fftfreq(size, d=1.0 / size) * k
        self.table = (size / self.lam) * np.fft.ifft(spec).real + self._tails(self.nodes)
        self.slope = ((size / self.lam) * np.fft.ifft(1j * freq * spec).real
                      + self._tails_slope(self.nodes))
        # near the origin the Clausen kinks defeat interpolation: there the tails are exact
        nn = np.arange(-16, 17) * self.dx
        self._near_table = (nn[0], self._tails(nn), self._tails_slope(nn))
        self._cubic = _periodic_cubic(self.table, self.slope, self.dx)

    def _tails(self, d):
        kd = self.k * np.asarray(d, dtype=float)
        return self.tail2 * clausen2(kd) + self.tail3 * clausen3(kd)

    def _tails_slope(self, d):
        """d/dx of the tails (d/dθ Cl2 = -log|2 sin(θ/2)|, d/dθ Cl3 = -Cl2); 0 at the origin,
        where the exact near-origin correction takes over."""
        kd = self.k * np.asarray(d, dtype=float)
        with np.errstate(divide="ignore"):
            lg = -np.log(np.abs(2 * np.sin(kd / 2)))
        lg[~np.isfinite(lg)] = 0.0
        return self.k * (self.tail2 * lg - self.tail3 * clausen2(kd))

    def remainder(self, d) -> np.ndarray:
        """R(d): the viscoelastic part of the kernel (zero for elastic)."""
        d = np.asarray(d, dtype=float)
        if self.table is None:
            return np.zeros_like(d)
        return self.remainder_matrix(d.ravel(), np.zeros(1)).reshape(d.shape)

    def remainder_matrix(self, x, y) -> np.ndarray:
        """R(x_j − y_i) as a len(x) × len(y) matrix (the hot path of the response matrices:
        one compiled pass, no temporaries)."""
        x, y = np.asarray(x, dtype=float).ravel(), np.asarray(y, dtype=float).ravel()
        r = np.empty((x.size, y.size))
        if self.table is None:
            r[...] = 0.0
            return r
        near = np.empty(r.size, dtype=np.intp)
        # the cubic table; near the origin (and its periodic image) the Clausen kinks defeat
        # interpolation: there (within 16 cells) the tails are added exactly
        n_near = kernels.periodic_cubic(self._cubic, x, y, self.lam, 1.0 / self.dx, 16.0, r,
                                        near)
        if n_near:
            jj, ii = np.divmod(near[:n_near], y.size)
            dn = x[jj] - y[ii]
            dn = dn - self.lam * np.round(dn / self.lam)
            x0, tv, ts = self._near_table
            corr = self._tails(dn) - _hermite(tv, ts, (dn - x0) / self.dx, self.dx)
            r.reshape(-1)[near[:n_near]] += corr
        return r

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


#: Gauss-Chebyshev nodes for the analytic part of the kernel (log sinc): enough for 1e-12
Q_ANALYTIC = 1024


@dataclass
class Domain:
    """Contact domain [-l1, l2] with its spectral discretisation."""

    l1: float
    l2: float
    M: int
    Q: int

    def __post_init__(self):
        self._geometry(0.5 * (self.l1 + self.l2), 0.5 * (self.l2 - self.l1))

    @classmethod
    def centred(cls, a: float, c: float, M: int, Q: int) -> Domain:
        """The domain of half-width a centred at c (a kept exactly: it keys the shape cache
        of :meth:`Sinusoid1D.shape`)."""
        dom = cls.__new__(cls)
        dom.l1, dom.l2, dom.M, dom.Q = a - c, a + c, M, Q
        dom._geometry(a, c)
        return dom

    def _geometry(self, a, c):
        self.a, self.c = float(a), float(c)
        j = np.arange(1, self.M + 1)
        self.xi = np.cos((2 * j - 1) * np.pi / (2 * self.M))
        self.x = self.c + self.a * self.xi
        self.phi = (np.arange(self.Q) + 0.5) * np.pi / self.Q
        self.xq = self.c + self.a * np.cos(self.phi)  # Gauss-Chebyshev nodes

    def series(self, coef) -> np.ndarray:
        """Σ_m c_m cos(m φ_j) at the Q Gauss-Chebyshev angles (a DCT-III)."""
        x = np.zeros(self.Q)
        x[: self.M] = coef
        x[1: self.M] *= 0.5
        return sfft.dct(x, type=3)

    def response(self, kernel: Kernel1D, x) -> np.ndarray:
        """Matrix A with u(x) = A @ c for points x (any position within a period).

        Three parts: the log|k d| singularity through exact moments; the analytic rest of
        the E_tip log kernel, log sinc, by Gauss-Chebyshev on at most ``Q_ANALYTIC`` nodes;
        the viscoelastic remainder R on all ``Q`` nodes (it varies on the relaxation length).
        """
        x = np.asarray(x, dtype=float)
        lam = kernel.lam
        x = self.c + np.mod(x - self.c + lam / 2, lam) - lam / 2  # nearest periodic image
        xi = (x - self.c) / self.a
        A = _log_moments(xi, self.M)
        A[:, 0] += np.pi * (np.log(self.a) + np.log(kernel.k))
        A *= -kernel.cL * self.a
        qe = self.analytic_nodes(x, lam)
        xq = self.xq if qe == self.Q else self.c + self.a * np.cos(
            (np.arange(qe) + 0.5) * np.pi / qe)
        F = log_sinc(kernel.k * (x[:, None] - xq[None, :]))
        A -= (kernel.cL * self.a * np.pi / (2 * qe)) * sfft.dct(F, type=2, axis=1)[:, : self.M]
        if kernel.table is not None:
            F = kernel.remainder_matrix(x, self.xq)
            A += (self.a * np.pi / (2 * self.Q)) * sfft.dct(F, type=2, axis=1)[:, : self.M]
        return A

    def analytic_nodes(self, x, lam: float) -> int:
        """Gauss-Chebyshev nodes for the log sinc part at the points x (nearest images).

        log sinc(k(x − x')) is analytic in x' except at x' = x ± λ; the nearest of these lies
        δ = λ − a − max|x − c| beyond the contact, so its Chebyshev series in σ decays as
        ρ⁻ⁿ with ρ = s + √(s² − 1), s = 1 + δ/a.  The moments up to M − 1 then need
        M + n(1e-16) nodes (generously: exact for polynomials of degree 2·nodes − M);
        at most ``Q_ANALYTIC`` (and Q) — near full contact δ → 0 and the cap holds.
        """
        delta = lam - self.a - float(np.max(np.abs(np.asarray(x) - self.c)))
        s = 1.0 + max(delta, 0.0) / self.a
        rho = s + math.sqrt(s * s - 1.0)
        n_f = 37.0 / math.log(rho) if rho > 1.0 else np.inf  # ρ^-n = 1e-16
        need = self.M + n_f + 16
        qe = Q_ANALYTIC if not np.isfinite(need) else int(sfft.next_fast_len(int(need), real=True))
        return int(min(self.Q, max(min(qe, Q_ANALYTIC), self.M)))

    def pressure(self, coef, x) -> np.ndarray:
        xi = (np.asarray(x, float) - self.c) / self.a
        inside = np.abs(xi) < 1
        out = np.zeros_like(xi)
        T = np.cos(np.arange(self.M)[None, :] * np.arccos(np.clip(xi[inside], -1, 1))[:, None])
        out[inside] = (T @ coef) / np.sqrt(1 - xi[inside] ** 2)
        return out

    def integrate(self, coef, values) -> float:
        """∫ p f dx over the contact, f given at the Gauss-Chebyshev nodes ``self.xq``."""
        return float(self.a * (np.pi / self.Q) * np.dot(self.series(coef), values))

    def integrate_range(self, coef, f, x_lo: float, x_hi: float, n: int | None = None) -> float:
        """∫_{x_lo}^{x_hi} p f dx over a sub-range of the contact, f smooth.

        In the angle variable (x = c + a cos φ) ``p dx = a Σ c_m cos(mφ) dφ`` is smooth, so
        Gauss-Legendre in φ is spectrally accurate whatever the edge singularities.
        """
        n = n or self.M + 48
        lo = np.arccos(np.clip((x_hi - self.c) / self.a, -1, 1))
        hi = np.arccos(np.clip((x_lo - self.c) / self.a, -1, 1))
        t, wt = _leggauss(n)
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

    def solve_domain(self, l1, l2, *, delta=None, p_mean=None) -> State:
        """Solve Eq. (15) on [-l1, l2] at given Δ, or at given mean pressure p∞ (Δ solved)."""
        return self.state_of(self.domain_pair(l1, l2), delta=delta, p_mean=p_mean)

    def state_of(self, pair, *, delta=None, p_mean=None) -> State:
        """The state of a :meth:`pair_at` at given Δ or mean pressure p∞ (Δ solved)."""
        dom, cw, c1 = pair
        if delta is None:
            # p∞ = a π c0 / λ fixes Δ
            delta = (p_mean * self.lam / (dom.a * np.pi) - cw[0]) / c1[0]
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
        return A @ state.coef - self.w(x, state.delta)

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
        adv = self.state_of(self.advanced_pair(base.domain, side, a0), delta=base.delta)
        xs, ws, R = self._strip(base.domain, side, a0)  # for g₋ p₊ ~ (old)^½ (new)^-½
        g_minus = R @ base.coef - self.w(xs, base.delta)
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
        """Edge residuals (trailing, leading) of the domain of half-width a centred at c,
        y = (a, c), at given Δ or p∞."""
        a, c = y
        if not (a > 0 and 2 * a < self.lam * 0.999):
            return np.array([1e3, 1e3])
        pair = self.pair_at(a, c)
        dom, cw, c1 = pair
        delta = (value if control == "delta"
                 else (value * self.lam / (dom.a * np.pi) - cw[0]) / c1[0])
        return np.array([self.edge_residual(self.edge_law(pair, side), delta, a)
                         for side in (1, 2)])

    def p_star(self):
        """p* = E0* k Λ/2 (Westergaard full-contact pressure), with E0 = ``E_ref``."""
        return self.E_ref / (1 - self.material.nu**2) * self.k * self.amp / 2

    def equilibrium(self, *, delta=None, p_mean=None, guess=None, tol=1e-11, ftol=1e-8,
                    fatol=1e-10):
        """Partial-contact equilibrium at given Δ or p∞ from a guess (l1, l2).

        A state whose surface crosses the rigid profile outside the contact (by more than
        1e-6 Λ at 64 points of the separated part) is not an equilibrium: not converged, with
        the reason in ``info['message']`` (:meth:`robust_equilibrium` then tries the next
        guess).

        Converged when both edge residuals ``√(δL_i/(a0 Δγ)) - 1`` (or the SIF residuals) are
        below ``ftol`` — MINPACK's own flag is not used, since at tiny a0 the residual has a
        noise floor of ~1e-10 that stops its step-size test, not the balance.  The search
        stops as soon as both residuals are below ``fatol`` (the edges then sit within
        ~fatol/k of the balance; MINPACK's step test alone took as many evaluations again
        at the residuals' round-off level, measured at ζ = 1e-3), or at its step size ``tol``.
        """
        control, value = ("delta", delta) if delta is not None else ("p_mean", p_mean)
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
        st.info = {"converged": ok, "message": message, "nfev": count[0],
                   "residual": float(np.max(np.abs(f))), "residuals": tuple(f),
                   "control": (control, value), "interpenetration": over}
        return st

    def guesses(self, control, value):
        """Starting edges to try: symmetric elastic contacts with E0, |E(kv)| and E∞."""
        out = [self.elastic_guess(control, value)]
        if self.kernel.visco:
            for E in (abs(self.material.modulus(np.array([self.k * self.v]))[0]),
                      self.material.Einf):
                out.append(self.elastic_guess(control, value, E))
        return out

    def robust_equilibrium(self, *, delta=None, p_mean=None, guess=None):
        """:meth:`equilibrium` from ``guess``, then from each of :meth:`guesses`.

        With adhesion the load (or Δ) may have several equilibria: a converged state on the
        falling branch (:func:`branch_slope` ≤ 0, beyond the snap-in maximum: unstable) is
        kept only if no guess reaches the rising branch — measured: the ζ sweep at p̃∞ = 0.15
        continued from ζ = 0.3 (ã = 1.37) reached ã = 2.19 at ζ = 1, where dp̃/dã < 0, while
        the elastic guess gives the rising ã = 0.90.  ``info['branch_slope']`` is reported.
        """
        control, value = ("delta", delta) if delta is not None else ("p_mean", p_mean)
        st = falling = None
        tried = []
        for g in ([guess] if guess is not None else []) + self.guesses(control, value):
            g = np.asarray(g, dtype=float)
            if any(np.allclose(g, t, rtol=1e-9, atol=0) for t in tried):
                continue  # the same start again (e.g. |E(kv)| ≈ E0 at small ζ) would fail again
            tried.append(g)
            st = self.equilibrium(guess=g, **{control: value})
            if not st.info["converged"]:
                continue
            st.info["branch_slope"] = (branch_slope(self, st, control) if self.dgamma > 0
                                       else np.inf)  # without adhesion p(a) only rises
            if not st.info["branch_slope"] <= 0:
                return st
            falling = falling or st
        return falling or st

    def elastic_guess(self, control, value, E=None):
        """Symmetric Johnson (1995) contact with modulus E (default E0) at the same load."""
        from . import reference as ref

        beta = (self.material.E0 if E is None else E) / self.E_ref
        Gam = (1 - self.material.nu**2) * self.dgamma / (np.pi * self.E_ref * self.k
                                                         * self.amp**2)
        if control == "p_mean":
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
        return float(4 * (1 - self.material.nu**2) / (self.lam**2 * state.p_mean) * total)

    def friction(self, state: State):
        """μ of Eq. (19): -(1/(λ p∞)) ∫ p u' dx with u' = w' = -Λk sin(kx) on the contact.

        Undefined (nan) at exactly zero mean pressure; see :meth:`friction_force`."""
        if state.p_mean == 0.0:
            return np.nan
        return self.friction_force(state) / (self.lam * state.p_mean)

    def friction_force(self, state: State) -> float:
        """Tangential force per unit length and period, -∫ p u' dx (N/m)."""
        d = state.domain
        up = -self.amp * self.k * np.sin(self.k * d.xq)
        return -d.integrate(state.coef, up)


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


#: the smallest positive advance width ã0 = k a0 the strip quadrature resolves: below it the
#: edge residual's rounding floor (g₋ ~ K√a0 from u - w of order Λ) nears the tolerance 1e-8
#: (measured at p̃ = 0.15: 1e-10 at ã0 = 1e-6, 1e-9 at 3e-7, 3e-8 at 1e-7, not converged)
A0_MIN = 1e-6


def _check_inputs(**kw):
    rng = {"zeta": (0.0, np.inf, True), "beta": (1.0, 1e8, False), "Gamma": (0.0, 10.0, False),
           "a0_tilde": (0.0, 1.0, False)}
    for name, value in kw.items():
        lo, hi, inf_ok = rng[name]
        v = float(value)
        if np.isnan(v) or v < lo or (v > hi and not (inf_ok and np.isinf(v))):
            raise ValueError(f"{name} = {value!r} is outside the allowed range [{lo}, {hi}]"
                             + (" or inf" if inf_ok else ""))
        if name == "a0_tilde" and 0.0 < v < A0_MIN:
            raise ValueError(f"a0_tilde = {value!r} is outside the allowed range: 0 (the strict "
                             f"limit) or [{A0_MIN:g}, {hi}]; a smaller advance width is not "
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
    delta: float = 0.0  # detached under load control: Δ̃ at the pull-off it detached from


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
        if not st.info["converged"] and guess != (0.0, None):
            st = branch_point(self.pr, a, (0.0, None))
        if st.info["converged"]:
            self.solved[a] = ((st.l2 - st.l1) / 2, st.delta)
        return st

    def at(self, a: float):
        """(p̃, Δ̃) of the branch point at ã (nan, nan where none is found)."""
        st = self.state(a)
        if not st.info["converged"]:
            return np.nan, np.nan
        return st.p_mean / self.pr.p_star(), st.delta / self.pr.amp

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
    """The verified state at mean pressure p∞ (``control`` 'p_mean') or penetration Δ
    ('delta') of a dimensionless problem (:func:`dimensionless_problem`).

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
    load = control == "p_mean"
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
                           delta=0.0 if load else v)
    st = pr.robust_equilibrium(guess=guess, **{control: value})
    falling = None
    if st.info["converged"]:
        slope = st.info.get("branch_slope", np.inf)
        if stability and not (np.isfinite(slope) and slope > 0):
            slope = _slope(pr, st, control)  # adhesiveless (inf: not computed) or not found
        st.info["branch_slope"] = slope
        scale = pr.k * (pr.p_star() if load else pr.amp)
        if slope > 0 or not stability:
            summ = _summary(pr, st)
            if any(np.isnan(x) for k_, x in summ.items() if stability or k_ != "branch_slope"):
                return Verdict("not_converged", "balanced, but a scalar of the state is nan",
                               residual=st.info["residual"])
            return Verdict("partial", f"{st.info['message']}; rising branch, "
                           f"d{'p̃' if load else 'Δ̃'}/dã = {slope / scale:.3g} > 0", st,
                           st.info["residual"])
        if slope <= 0:
            falling = st
    elif pr.underresolved:  # the branch trace at this resolution would take minutes
        return Verdict("not_converged", f"{st.info['message']}; {pr.underresolved}",
                       residual=st.info["residual"])
    return _branch_verdict(pr, control, v, st, falling)


def _branch_verdict(pr: Sinusoid1D, control: str, v: float, st: State, falling) -> Verdict:
    """:func:`_verdict` where the direct search found no stable equilibrium: the branch is
    traced on :data:`VERDICT_GRID` and the control value ``v`` (p̃ or Δ̃) placed on it."""
    from scipy.optimize import brentq

    load = control == "p_mean"
    col, name = (0, "p̃") if load else (1, "Δ̃")
    note = ""
    if falling is not None:
        s = falling.info["branch_slope"] / (pr.k * (pr.p_star() if load else pr.amp))
        note = (f"; the equilibrium found at ã = {pr.k * falling.domain.a:.4g} lies on the "
                f"falling branch (d{name}/dã = {s:.3g} ≤ 0: unstable under "
                f"{'load' if load else 'displacement'} control)")

    def unsettled(why):
        if falling is not None:
            return Verdict("unstable", why + note, falling, falling.info["residual"])
        return Verdict("not_converged", f"{why}; direct search: {st.info['message']}",
                       residual=st.info.get("residual", np.nan))

    br = _Branch(pr)
    A, P, D = br.trace(VERDICT_GRID / pr.k)
    if A.size == 0:
        return unsettled(f"no equilibrium branch found (ã from {VERDICT_GRID[0]:g} to "
                         f"{VERDICT_GRID[-1]:g}){_edge_census(pr, VERDICT_GRID / pr.k)}")
    V = P if load else D
    if int(np.argmax(V)) == A.size - 1:  # still rising at the end of the grid: on to 99.6 %
        A2, P2, D2 = br.trace(np.linspace(A[-1], 0.498 * pr.lam, 5)[1:])
        A, P, D = (np.concatenate(z) for z in ((A, A2), (P, P2), (D, D2)))
        V = P if load else D
    n = A.size
    span = f"(the branch traced from ã = {pr.k * A[0]:.3g} to {pr.k * A[-1]:.3g})"

    def around(idx, sign):  # the extremum near A[idx] refined (only where it decides)
        lo, hi = (A[idx - 1] if idx > 0 else A[0] / 10), A[min(idx + 1, n - 1)]
        a_, v_ = br.refine(col, sign, lo, hi, xatol=1e-4)
        return (a_, v_) if sign * v_ <= sign * V[idx] else (A[idx], V[idx])

    # the rising part: from the smallest value before the largest (the pull-off) up to it
    i = int(np.argmax(V))
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
                           + note, residual=0.0, delta=br.at(a_lo)[1] if load else v)
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
        if not pt.info["converged"]:
            continue
        ctl = {control: v * (pr.p_star() if load else pr.amp)}
        eq = pr.equilibrium(guess=(pt.l1, pt.l2), **ctl)  # the same residual test as above
        if not eq.info["converged"]:
            continue
        eq.info["branch_slope"] = _slope(pr, eq, control)
        if eq.info["branch_slope"] > 0:
            s = eq.info["branch_slope"] / (pr.k * (pr.p_star() if load else pr.amp))
            return Verdict("partial", f"{eq.info['message']}; found on the rising branch "
                           f"by tracing {name}(ã), d{name}/dã = {s:.3g} > 0" + note, eq,
                           eq.info["residual"])
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
    control, value = st.info.get("control", ("p_mean", None))
    # the prescribed load, not its rounding (μ̄ at p̃ = 0 is then ±inf, not F/1e-19)
    pm = value if control == "p_mean" and value is not None else st.p_mean
    out = {
        "a_tilde": k * (st.l1 + st.l2) / 2, "e_tilde": k * (st.l2 - st.l1) / 2,
        "p_tilde": pm / pstar, "delta_tilde": st.delta / pr.amp,
        # an elastic contact is symmetric: no friction (the quadrature leaves ~1e-17, which
        # at zero load would read as an infinite μ̄); viscoelastic at zero load: ±inf
        "mu_bar": (_quotient(pr.friction_force(st), lam * pm) / (k * pr.amp)
                   if pr.kernel.visco else 0.0),
        "K1": st.K[0], "K2": st.K[1],
    }
    slope = st.info.get("branch_slope", np.nan)
    out["branch_slope"] = slope / (k * (pstar if control == "p_mean" else pr.amp))
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


SCALARS = {
    "a_tilde": "dimensionless contact semi-width k a",
    "e_tilde": "dimensionless eccentricity k e (> 0: toward the leading edge)",
    "p_tilde": "dimensionless mean pressure 2(1-ν²)p∞/(E0 k Λ)",
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
    ``guess`` = (k l1, k l2) for continuation.  Scalars: a_tilde, e_tilde, p_tilde,
    delta_tilde, mu_bar, mu_bar_adhesive, G1_over_dgamma, G2_over_dgamma, branch_slope,
    status, and the adhesiveless a, e, μ at the same load; fields sigma_tilde (= σ/p* = -p̃)
    and u_tilde (= u/Λ) on the contact mesh x_tilde (the period for full contact and
    detached states).  The status is verified (:func:`_verdict`), its reason is the
    ``solver_message`` attribute; no scalar of a partial, full_contact, detached or unstable
    state is nan (not_converged: all nan).
    """
    import xarray as xr

    from .io import STATUS, attrs

    if (p_tilde is None) == (delta_tilde is None):
        raise ValueError("give exactly one of p_tilde (load control) and delta_tilde")
    for name, v in (("p_tilde", p_tilde), ("delta_tilde", delta_tilde)):
        if v is not None and not np.isfinite(v):
            raise ValueError(f"{name} = {v!r} must be finite")
    if delta_tilde is not None and delta_tilde >= 1.0:
        raise ValueError(f"delta_tilde = {delta_tilde!r} is outside the allowed range "
                         "(-inf, 1): Δ̃ = 1 is full contact at an undetermined load (the mean "
                         "gap vanishes) and no state has Δ̃ > 1; use p_tilde")
    pr = dimensionless_problem(zeta, beta, Gamma, a0_tilde, adhesive=Gamma > 0, modes=modes,
                               quad=quad)
    ratio = _modulus_ratio(zeta, beta)
    control, value = (("p_mean", p_tilde * pr.p_star()) if p_tilde is not None
                      else ("delta", delta_tilde * pr.amp))
    vd = _verdict(pr, control, value, ratio, guess)
    if vd.status in ("full_contact", "detached"):
        vals, x, p, u = _closed_form(vd.status, p_tilde, vd.delta, ratio)
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
            u = pr.w(x, st.delta) / pr.amp
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
    vd = _verdict(ref, "p_mean", pt * ref.p_star(), ratio, stability=False)
    if vd.status in ("full_contact", "detached"):
        vals = _closed_form(vd.status, pt, vd.delta, ratio)[0]
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
    (G = 0, no adhesive friction).  Detached: no contact, no pressure, a flat surface, with
    ``delta_tilde`` the prescribed Δ̃ or, under load control, the Δ̃ of the pull-off (0 without
    adhesion).  ã does not change with the load: branch_slope 0 (no partial branch)."""
    x = np.linspace(-np.pi, np.pi, NXI)
    if status == "full_contact":
        p = p_tilde + np.real(ratio * np.exp(1j * x))
        vals = dict(a_tilde=np.pi, e_tilde=0.0, p_tilde=p_tilde, delta_tilde=1.0,
                    mu_bar=_quotient(-np.imag(ratio), 2 * p_tilde), u=np.cos(x))
    else:
        p = np.zeros(NXI)
        vals = dict(a_tilde=0.0, e_tilde=0.0, p_tilde=0.0 if p_tilde is None else p_tilde,
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
    if progress:
        from tqdm import tqdm

        it = tqdm(order, desc="zeta sweep")
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


def branch_point(pr: Sinusoid1D, a: float, guess=(0.0, None)):
    """Equilibrium at half-width a: the eccentricity e and penetration Δ at which both edges
    balance.  Returns State (``info['converged']``).

    The state is linear in Δ for a fixed domain, so for each trial e the trailing-edge balance
    gives Δ in closed form (:meth:`Sinusoid1D.edge_balance_delta`) and only the leading-edge
    residual is left: a scalar secant search in e, which at fixed a costs no domain build
    (:meth:`Sinusoid1D.shape`).  A 2D Newton search in (e, Δ) is the fallback.
    """
    e, d, res, message = _branch_edges(pr, a, guess)
    st = pr.state_of(pr.pair_at(a, e), delta=d)
    if pr.dgamma and pr.a0:
        pr.release_rates(st)
    over = pr.interpenetration(st)
    if over > 1e-6:  # both edges balance, but the surface crosses the profile elsewhere
        message = f"inadmissible: interpenetrates by {over:.1e} Λ outside the contact"
    st.info = {"converged": bool(res < 1e-8 and over <= 1e-6), "message": message,
               "residual": float(res)}
    return st


def branch_slope(pr: Sinusoid1D, st: State, control: str, step: float = 1e-4) -> float:
    """d p∞/d a (load control) or d Δ/d a (displacement control) along the equilibrium
    branch at the state ``st``, one-sided over a step of ``step``·λ in the half-width.

    The rising branch (slope > 0) is the one reached by loading from first contact: in the
    elastic limits it is the stable branch of Johnson (1995) under that control (JKR's
    criterion), and beyond the snap-in maximum the load falls again toward full contact on
    the unstable branch.  nan if the neighbouring branch point is not found."""
    a = st.domain.a + step * pr.lam
    e, d, res, _ = _branch_edges(pr, a, (st.domain.c, st.delta))
    if not res < 1e-8:
        return np.nan
    if control == "delta":
        return float((d - st.delta) / (step * pr.lam))
    p = pr.state_of(pr.pair_at(a, e), delta=d).p_mean
    return float((p - st.p_mean) / (step * pr.lam))


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
            return pr._residual((a, e), "delta", d)

        sol2 = root(F2, np.array([e0, d0], float), method="hybr", options={"xtol": 1e-12})
        (e, d), res, message = sol2.x, float(np.max(np.abs(sol2.fun))), sol2.message
    return e, d, res, message


def special_points(zeta: float, beta: float, Gamma: float, *, a0_tilde: float,
                   modes: int | None = None, n: int = 40, cheb: int = 20):
    """Pull-off (load and fixed Δ), zero-load contact, snap-in to full contact and toughness.

    Traces the branch in ã (grid refined toward small ã), refines each extremum by a bounded
    scalar minimisation, and evaluates the toughness of Eq. (24), T̃ = 2π∫ p̃ dΔ̃ from p̃ = 0 to
    the fixed-Δ pull-off, exactly on Chebyshev fits of p̃(ã) and Δ̃(ã) through ``cheb`` points.
    Returns a dict with the keys of :func:`spectralbem.reference.johnson_special_points`.
    """
    from numpy.polynomial import chebyshev as C
    from scipy.optimize import brentq

    pr = dimensionless_problem(zeta, beta, Gamma, a0_tilde, modes=modes)
    a_grid = np.concatenate([np.geomspace(0.02, 0.5, n // 2, endpoint=False),
                             np.linspace(0.5, 3.0, n // 2)])
    br = _Branch(pr)
    at = br.at
    A, P, D = br.trace(a_grid)

    def refine(col, idx, sign):
        return br.refine(col, sign, A[max(idx - 1, 0)], A[min(idx + 1, A.size - 1)])

    # the snap-in point is the branch's load maximum; beyond it (toward full contact) the
    # load falls again on an unstable branch, possibly below the pull-off load: the minima
    # are sought on the part of the branch before the maximum
    imax = int(np.argmax(P))
    interior = 0 < imax < A.size - 1
    a_pmax, p_max = refine(0, imax, -1.0) if interior else (np.nan, np.nan)
    before = A <= A[imax] if interior else np.ones(A.size, bool)
    a_pmin, p_min = refine(0, int(np.argmin(np.where(before, P, np.inf))), 1.0)
    a_dmin, d_min = refine(1, int(np.argmin(np.where(before, D, np.inf))), 1.0)
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
                a_dmin=a_dmin, delta_min=d_min, p_dmin=at(a_dmin)[0], T=T,
                branch={"a_tilde": A, "p_tilde": P, "delta_tilde": D})
