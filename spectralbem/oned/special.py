"""Special functions and interpolation of the 1D method: the Clausen functions Cl2, Cl3
(the kernel's 1/n² and 1/n³ tails), log sinc, Gauss-Legendre nodes and cubic Hermite
interpolation (see :mod:`spectralbem.oned`)."""

from __future__ import annotations

import functools
import math

import numpy as np
from scipy.special import bernoulli

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
