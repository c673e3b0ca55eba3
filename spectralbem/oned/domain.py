"""The contact domain [-l1, l2] of the 1D method and its Chebyshev pressure basis with
the built-in √ edge singularity (see :mod:`spectralbem.oned`)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.fft as sfft

from .kernel import Kernel1D
from .special import _leggauss, log_sinc


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
