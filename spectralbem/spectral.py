"""Periodic cell and the spectral response operator (seed Eqs. (1), (2), (A.3), (A.8), (A.14)).

Pressure → displacement on an Nx × Ny periodic grid of a cell Lx × Ly::

    u(q) = Ĉ(q) p(q),   Ĉ(q) = 2(1-ν²) S(|q|d) / (E(q·v) |q|)      (A.3 with A.8, p = -σ)

* Array layout: ``f[i, j]`` is the value at ``x = i·hx, y = j·hy`` (cell centres); axis 0 is x.
* ``u`` is positive *into* the slab, ``p`` positive in compression (docs/derivations.md §1).
* The q = 0 mode follows the layer (:mod:`spectralbem.layers`): dropped for the half-space and
  the pressure-loaded layer (zero-mean gauge), finite for the glued layer.
* ``delayed = "cell"`` (default): the glassy part 2(1-ν²)S/(E∞|q|) sampled, the delayed part
  (1/E(ω) − 1/E∞) averaged over the cells with its aliased images
  (:mod:`spectralbem.cell_average`); ``"sampled"``: Ĉ at the grid's wavevectors.
* Elastic scenes (or v = 0) build a real kernel and never evaluate E(ω); a half-space never
  evaluates S.
* Even/odd split (Eq. 2): C^E has kernel Re Ĉ (symmetric matrix), C^O has i Im Ĉ
  (antisymmetric matrix).
* Nyquist modes: the kernel is made exactly Hermitian on the discrete grid,
  Ĉ_k ← ½(Ĉ_k + conj Ĉ_{-k}), so the operator is an exact real matrix
  (docs/derivations.md §8): at the self-conjugate bins this zeroes Im Ĉ.  The spectral
  derivative is treated the same way.
* One application costs one forward r2c and one inverse c2r FFT; the 1/(Nx Ny) normalisation is
  folded into the stored kernel.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from . import backend as _backend
from .cell_average import delayed_kernel
from .conventions import shown
from .keys import DELAYED, DELAYED_DEFAULT
from .layers import HalfSpace, Layer
from .materials import Material

__all__ = ["Cell", "SpectralOperator", "GridError"]


class GridError(ValueError):
    """Invalid periodic-cell parameter."""


@dataclass(frozen=True)
class Cell:
    """Rectangular periodic cell ``Lx × Ly`` (m) sampled by ``Nx × Ny`` cells."""

    Lx: float
    Ly: float
    Nx: int
    Ny: int

    def __post_init__(self):
        for name in ("Lx", "Ly"):
            v = getattr(self, name)
            if not np.isfinite(v) or v <= 0:
                raise GridError(f"{name} = {shown(v)} must be a finite length > 0")
        for name, lo in (("Nx", 4), ("Ny", 1)):
            v = getattr(self, name)
            if int(v) != v or v < lo or v > 65536:
                raise GridError(f"{name} = {shown(v)} must be an integer in [{lo}, 65536]")
            object.__setattr__(self, name, int(v))

    # -- geometry ---------------------------------------------------------------------------
    @property
    def shape(self) -> tuple:
        return (self.Nx, self.Ny)

    @property
    def hx(self) -> float:
        return self.Lx / self.Nx

    @property
    def hy(self) -> float:
        return self.Ly / self.Ny

    @property
    def cell_area(self) -> float:
        return self.hx * self.hy

    @property
    def area(self) -> float:
        return self.Lx * self.Ly

    @property
    def x(self) -> np.ndarray:
        return np.arange(self.Nx) * self.hx

    @property
    def y(self) -> np.ndarray:
        return np.arange(self.Ny) * self.hy

    def coordinates(self, centred: bool = False):
        """Meshgrid (X, Y), optionally centred on the middle of the cell."""
        x, y = self.x, self.y
        if centred:
            x = x - self.Lx / 2
            y = y - self.Ly / 2
        return np.meshgrid(x, y, indexing="ij")

    def wavevectors(self, half: bool = True):
        """(qx, qy) in rad/m on the half (rfft) or full spectrum, broadcastable to its shape."""
        qx = 2 * np.pi * np.fft.fftfreq(self.Nx, self.hx)[:, None]
        f = np.fft.rfftfreq if half else np.fft.fftfreq
        qy = 2 * np.pi * f(self.Ny, self.hy)[None, :]
        return qx, qy

    def hermitian_half(self, full: np.ndarray) -> np.ndarray:
        """Enforce F_k = conj F_{-k} on a full-grid multiplier and return its rfft half."""
        flipped = np.roll(full[::-1, ::-1], shift=(1, 1), axis=(0, 1))  # F_{-k}
        sym = 0.5 * (full + np.conj(flipped))
        return sym[:, : self.Ny // 2 + 1]

    def rfft_weights(self) -> np.ndarray:
        """Multiplicity of each half-spectrum column in the full spectrum (for Parseval sums)."""
        w = np.full(self.Ny // 2 + 1, 2.0)
        w[0] = 1.0
        if self.Ny % 2 == 0:
            w[-1] = 1.0
        return w[None, :]

    def derivative_multiplier(self, direction) -> np.ndarray:
        """Half-spectrum multiplier i q·d̂ of the spectral derivative along unit vector d̂,
        hermitian on the grid: i q·d̂ is odd, so its Nyquist components (the self-conjugate
        bins of an even-sized axis) are zero.  Built on the half spectrum (one array)."""
        dx, dy = direction
        qx, qy = self.wavevectors(half=True)  # fresh arrays
        if self.Nx % 2 == 0:
            qx[self.Nx // 2] = 0.0
        if self.Ny % 2 == 0:
            qy[:, -1] = 0.0
        return 1j * (qx * dx + qy * dy)

    def derivative(self, f: np.ndarray, direction=(1.0, 0.0)) -> np.ndarray:
        """Spectral directional derivative d̂·∇f (Nyquist components zeroed, exact real matrix)."""
        return np.fft.irfft2(np.fft.rfft2(f) * self.derivative_multiplier(direction), s=self.shape)


class SpectralOperator:
    """u = C p on a periodic cell: material, layer and sliding velocity define Ĉ(q).

    Parameters
    ----------
    cell : Cell
    material : Material
    layer : Layer, default HalfSpace()
    velocity : (vx, vy) in m/s, the velocity of the indenter relative to the slab (the fields
        move as f(x - v t)); only used when the material is viscoelastic.
    threads : FFT threads (None: :func:`spectralbem.fft.get_threads`).
    backend : the compute backend, a name or a :class:`~spectralbem.backend.Backend`
        (None: ``SPECTRALBEM_BACKEND``, default ``"cpu"``).
    delayed : viscoelastic operators: ``"cell"`` (default: the glassy part sampled, the
        delayed part averaged over the cells, :mod:`spectralbem.cell_average`) or
        ``"sampled"`` (Ĉ at the grid's wavevectors); ignored by elastic operators.
    """

    def __init__(self, cell: Cell, material: Material, layer: Layer | None = None,
                 velocity=(0.0, 0.0), threads: int | None = None, backend=None,
                 delayed: str = DELAYED_DEFAULT):
        if delayed not in DELAYED:
            raise GridError(f"delayed = {delayed!r} must be one of {DELAYED}")
        self.delayed = delayed
        self.backend = _backend.get(backend)
        self.cell = cell
        self.material = material
        self.layer = HalfSpace() if layer is None else layer
        v = np.asarray(velocity, dtype=float).reshape(-1)
        if v.shape != (2,) or not np.all(np.isfinite(v)):
            raise GridError(f"velocity = {shown(velocity)} must be two finite numbers (vx, vy) "
                            "in m/s")
        self.velocity = v
        self.viscoelastic = (not material.is_elastic) and bool(np.any(v != 0))
        self.threads = threads
        # the half spectrum scaled by the inverse transform's 1/(Nx Ny): the only copy of the
        # kernel kept (:attr:`kernel` unscales it; transposes are built by the solves that
        # need them, :meth:`multipliers`)
        self._k = self._build_kernel() / (cell.Nx * cell.Ny)
        self._plan = None

    @property
    def kernel(self) -> np.ndarray:
        """Ĉ on the half spectrum, unscaled (m/Pa): a new array (exact where Nx Ny is a
        power of two)."""
        return self._k * (self.cell.Nx * self.cell.Ny)

    # -- kernel -----------------------------------------------------------------------------
    def _build_kernel(self) -> np.ndarray:
        cell, mat, lay = self.cell, self.material, self.layer
        nu = mat.nu
        sampled = self.viscoelastic and self.delayed == "sampled"
        # only a sampled viscoelastic kernel is complex and needs both ±q to be made hermitian;
        # the others are built on the half spectrum (|q| is the same at qy = ±π/hy)
        qx, qy = cell.wavevectors(half=not sampled)
        q = np.hypot(qx, qy)
        qpos = np.where(q > 0, q, 1.0)
        if sampled:
            comp = mat.compliance(qx * self.velocity[0] + qy * self.velocity[1])
        elif self.viscoelastic:  # the glassy part sampled, the delayed part cell-averaged
            comp = 1.0 / mat.Einf
        else:
            comp = 1.0 / mat.E0
        k = 2.0 * (1.0 - nu**2) * comp / qpos
        if not lay.is_half_space:
            k = k * lay.factor(qpos, nu)
        k = k * np.ones(q.shape)  # broadcast a scalar compliance
        c0 = lay.q0_compliance(mat.E0, nu)
        k[0, 0] = 0.0 if c0 is None else c0
        if sampled:
            half = cell.hermitian_half(k)
        elif self.viscoelastic:
            half = k + delayed_kernel(cell, mat, lay, self.velocity)
        else:
            half = k
        if not np.all(np.isfinite(half)):
            raise FloatingPointError("the response kernel has non-finite entries")
        return np.ascontiguousarray(half)

    @functools.cached_property
    def span(self) -> float:
        """max |Ĉ| / min |Ĉ| over the modes with Ĉ ≠ 0 (1 when there are none): conjugate
        gradients need O(√span) iterations."""
        a = np.abs(self.kernel)
        nz = a[a > 0]
        return float(nz.max() / nz.min()) if nz.size else 1.0

    @property
    def symmetric(self) -> bool:
        """True when C = Cᵀ (elastic material or v = 0): CG applies."""
        return not self.viscoelastic

    def even_part(self) -> "SpectralOperator":
        """The symmetric operator C^E with kernel Re Ĉ (Eq. 2, even part): the in-phase
        compliance at each wavevector's frequency q·v; ``self`` when already symmetric."""
        return self._symmetric_with(self._k.real)

    def magnitude_part(self) -> "SpectralOperator":
        """The symmetric operator with kernel |Ĉ| (even in q, as |Ĉ(−q)| = |conj Ĉ(q)|): the
        compliance 1/|E(q·v)| with which contact-area theories of sliding rubber (Persson's)
        replace the viscoelastic slab; ``self`` when already symmetric."""
        return self._symmetric_with(np.abs(self._k))

    def relaxed_part(self) -> "SpectralOperator":
        """The operator of the relaxed elastic slab (E0, same layer, at rest): the start of
        the viscoelastic contact solvers where the sliding kernel is not wanted."""
        from .materials import Elastic

        return SpectralOperator(self.cell, Elastic(self.material.E0, self.material.nu),
                                self.layer, (0.0, 0.0), self.threads, self.backend)

    def _symmetric_with(self, kernel) -> "SpectralOperator":
        if self.symmetric:
            return self
        sym = SpectralOperator.__new__(SpectralOperator)
        sym.__dict__.update({k: v for k, v in self.__dict__.items()
                             if k not in ("span", "inverse_multipliers")})
        sym.viscoelastic = False
        sym._k = np.ascontiguousarray(kernel)  # scaled as self._k
        return sym

    @property
    def plan(self):
        """The backend's transform pair for this grid (its buffers are shared)."""
        if self._plan is None:
            self._plan = self.backend.plan(self.cell.shape, self.threads)
        return self._plan

    # -- application ------------------------------------------------------------------------
    def _apply(self, p: np.ndarray, k: np.ndarray, out: np.ndarray | None) -> np.ndarray:
        r = self.backend.apply_kernel(self.plan, p, k)
        if out is None:
            return r.copy()
        out[...] = r
        return out

    def apply(self, p: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """u = C p (one r2c + one c2r transform)."""
        return self._apply(p, self._k, out)

    def apply_transpose(self, p: np.ndarray, out: np.ndarray | None = None) -> np.ndarray:
        """Cᵀ p (kernel conj Ĉ): the adjoint used for δL_P attribution."""
        return self._apply(p, np.conj(self._k) if self.viscoelastic else self._k, out)

    def multipliers(self, transpose: bool = False) -> tuple:
        """(Ĉ, 1/Ĉ) on the half spectrum, scaled for :meth:`apply` and
        :meth:`apply_inverse`, or their transposes' (conj Ĉ, conj 1/Ĉ): the operator keeps
        the first pair only, a viscoelastic transpose pair is built on each call (two
        complex half-spectrum arrays; the fused masked solves apply the conjugates in the
        transform buffers instead, masked.PackedSystem)."""
        k, kinv = self._k, self.inverse_multipliers
        if transpose and self.viscoelastic:
            return np.conj(k), np.conj(kinv)
        return k, kinv

    def apply_even(self, p: np.ndarray) -> np.ndarray:
        """C^E p, kernel Re Ĉ (Eq. 2, even part)."""
        return self._apply(p, self._k.real.copy(), None)

    def apply_odd(self, p: np.ndarray) -> np.ndarray:
        """C^O p, kernel i Im Ĉ (Eq. 2, odd part)."""
        return self._apply(p, 1j * self._k.imag, None)

    def inverse_kernel(self) -> np.ndarray:
        """1/Ĉ on the half spectrum, scaled for use as a preconditioner (Fourier inverse).

        Where Ĉ = 0 (the dropped q = 0 mode) the stiffness of the lowest non-zero mode is used.
        """
        k = self.kernel
        inv = np.zeros_like(k)
        nz = k != 0
        inv[nz] = 1.0 / k[nz]
        if not nz[0, 0]:
            inv[0, 0] = np.abs(inv[nz]).min()
        return inv / (self.cell.Nx * self.cell.Ny)

    def apply_inverse(self, u: np.ndarray, out: np.ndarray | None = None,
                      transpose: bool = False) -> np.ndarray:
        """The unmasked inverse F⁻¹[1/Ĉ] F u (the Fourier preconditioner), or its transpose."""
        return self._apply(u, self.multipliers(transpose)[1], out)

    @functools.cached_property
    def inverse_multipliers(self) -> np.ndarray:
        """1/Ĉ, scaled as :meth:`inverse_kernel` (built once)."""
        return self.inverse_kernel()

    # -- energies and friction --------------------------------------------------------------
    def elastic_energy(self, p: np.ndarray) -> float:
        """U = ½ ∫ p u d²x = ½ ∫ p C^E p (Eq. 5 / B.5 with the compressive p), J per cell."""
        P = self.plan.forward(p)
        w = self.cell.rfft_weights()
        n = self.cell.Nx * self.cell.Ny
        return 0.5 * self.cell.cell_area * float(np.sum(w * self.kernel.real * np.abs(P) ** 2) / n)

    def dissipation_friction_force(self, p: np.ndarray, direction) -> float:
        """Spectral dissipation form of the friction force along d̂ (docs/derivations.md §5), in N.

        F = -∫ p (d̂·∇u) d²x = (1/A0) Σ_q (q·d̂) Im Ĉ(q) |p_q|²: it sees only C^O and is
        the viscoelastic dissipation rate divided by |v| when d̂ = v̂.
        """
        # the multiplier of the discrete derivative (Nyquist components zeroed)
        dm = self.cell.derivative_multiplier(direction).imag
        P = self.plan.forward(p)
        w = self.cell.rfft_weights()
        n = self.cell.Nx * self.cell.Ny
        s = np.sum(w * dm * self.kernel.imag * np.abs(P) ** 2) / n if self.viscoelastic else 0.0
        return float(s * self.cell.cell_area)
