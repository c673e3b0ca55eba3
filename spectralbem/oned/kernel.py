"""The periodic 1D kernel of seed Eq. (13) / (A.18): exact log part, Clausen tails, the
tabulated smooth rest (see :mod:`spectralbem.oned`)."""

from __future__ import annotations

import numpy as np

from .. import kernels
from ..materials import Material
from .special import _hermite, _periodic_cubic, clausen2, clausen3, log_sinc


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
