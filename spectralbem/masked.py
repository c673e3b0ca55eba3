"""Masked linear solves: given a contact mask A and the displacement on A, the pressure on A.

Solves ``(C p)_i = b_i`` for i ∈ A with ``p = 0`` off A (seed Eq. (15) on a grid).  C is the
:class:`~spectralbem.spectral.SpectralOperator`.

* Symmetric operator (elastic, or v = 0): conjugate gradients.
* Non-symmetric (viscoelastic sliding): BiCGSTAB with the Fourier preconditioner
  ``M = P F⁻¹[1/Ĉ] F P`` (docs/derivations.md §8), falling back to right-preconditioned
  GMRES(m) (m = 300 where memory allows) when BiCGSTAB breaks down or stagnates.  The
  masked matrix P C P has a positive-definite symmetric part (Re 1/E > 0), so both are well
  posed.
* Warm starts through ``x0``.  An iteration guard (``maxiter`` matrix-vector products) always
  terminates; the returned :class:`SolveResult` states whether the *true* residual
  ``‖b - A x‖/‖b‖`` met the tolerance.

The scipy Krylov implementations are used on the packed vector of mask values.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import LinearOperator, bicgstab, cg, gmres

from .spectral import SpectralOperator

#: the true residual must be below this multiple of rtol to count as converged
TRUE_RESIDUAL_MARGIN = 10.0


@dataclass
class SolveResult:
    """Outcome of a masked solve."""

    field: np.ndarray  # full-grid pressure, zero off the mask
    iterations: int  # operator applications (matvecs)
    residual: float  # true relative residual ‖b - A x‖/‖b‖ on the mask
    converged: bool
    message: str
    method: str


class MaskedSystem:
    """The packed masked operator ``x ↦ (C P x)|_A`` (and its transpose)."""

    def __init__(self, op: SpectralOperator, mask: np.ndarray, transpose: bool = False):
        mask = np.asarray(mask, dtype=bool)
        if mask.shape != op.cell.shape:
            raise ValueError(f"mask shape {mask.shape} != grid shape {op.cell.shape}")
        self.op = op
        self.mask = mask
        self.idx = np.flatnonzero(mask)
        self.n = self.idx.size
        self.transpose = transpose
        self._full = np.zeros(op.cell.shape)
        self._out = np.empty(op.cell.shape)
        self.matvecs = 0

    def expand(self, x: np.ndarray) -> np.ndarray:
        full = np.zeros(self.op.cell.shape)
        full.flat[self.idx] = x
        return full

    def matvec(self, x: np.ndarray) -> np.ndarray:
        self.matvecs += 1
        self._full.flat[self.idx] = x
        apply = self.op.apply_transpose if self.transpose else self.op.apply
        apply(self._full, out=self._out)
        return self._out.flat[self.idx].copy()

    def precondition(self, x: np.ndarray) -> np.ndarray:
        self._full.flat[self.idx] = x
        self.op.apply_inverse(self._full, out=self._out, transpose=self.transpose)
        return self._out.flat[self.idx].copy()

    def linear_operator(self) -> LinearOperator:
        return LinearOperator((self.n, self.n), matvec=self.matvec, dtype=np.float64)

    def preconditioner(self) -> LinearOperator:
        return LinearOperator((self.n, self.n), matvec=self.precondition, dtype=np.float64)


#: GMRES restart length (default), as far as the Krylov basis fits in RESTART_BYTES
RESTART_MAX = 300
RESTART_BYTES = 200 * 2**20

#: masks up to this many cells use unrestarted GMRES: measured on the sinusoid at β = 1e3,
#: ζ = 1 (≈100-cell masks) GMRES(60) stagnated at residual 1e-3 after 700 matvecs
FULL_GMRES_SIZE = 500


def solve_masked(op: SpectralOperator, mask: np.ndarray, rhs: np.ndarray, *, x0=None,
                 rtol: float = 1e-10, maxiter: int | None = None, method: str = "auto",
                 precondition: bool | None = None, transpose: bool = False,
                 restart: int | None = None) -> SolveResult:
    """Solve (C p)|_A = rhs|_A with p = 0 off A.

    Parameters
    ----------
    rhs : full-grid array; only its values on the mask are used.
    x0 : full-grid warm start (values on the mask are used).
    rtol : relative tolerance on ‖b - A x‖/‖b‖.
    maxiter : guard on matrix-vector products (default 20·√n + 500).
    method : 'auto' (CG if symmetric else BiCGSTAB→GMRES), 'cg', 'bicgstab' or 'gmres'.
    precondition : Fourier preconditioner; default on for non-symmetric systems.
    transpose : solve with Cᵀ (adjoint solve).
    restart : GMRES restart length; default ``RESTART_MAX`` (300) as far as its Krylov basis
        fits in ``RESTART_BYTES`` (200 MB), at least 60.  Measured on the rough 256² mask at
        β = 1e4, ζ = 10: GMRES(60) needs 5894 products, GMRES(300) 1370 (the guard is 2065).
        The basis exists only in the fallback; it can exceed the adhesive solve's memory
        budget of 25 N² arrays on mid-size grids (a 26k-cell mask at 512²: 63 MB, 30 arrays),
        which is why the cap is in bytes.
    """
    sys_ = MaskedSystem(op, mask, transpose=transpose)
    n = sys_.n
    shape = op.cell.shape
    if n == 0:
        return SolveResult(np.zeros(shape), 0, 0.0, True, "empty mask", "none")
    b = np.asarray(rhs, dtype=float).flat[sys_.idx].copy()
    if not np.all(np.isfinite(b)):
        raise ValueError("rhs has non-finite values on the mask")
    bnorm = float(np.linalg.norm(b))
    if bnorm == 0.0:
        return SolveResult(np.zeros(shape), 0, 0.0, True, "zero right-hand side", "none")
    x = np.zeros(n) if x0 is None else np.asarray(x0, dtype=float).flat[sys_.idx].copy()
    if not np.all(np.isfinite(x)):
        x = np.zeros(n)
    if maxiter is None:
        maxiter = int(20 * np.sqrt(n) + 500)
    if method == "auto":
        method = "cg" if op.symmetric else "bicgstab"
    if method not in ("cg", "bicgstab", "gmres"):
        raise ValueError(f"method = {method!r}; allowed: 'auto', 'cg', 'bicgstab', 'gmres'")
    if precondition is None:
        precondition = not op.symmetric
    if restart is None:
        restart = int(min(RESTART_MAX, max(60, RESTART_BYTES // (8 * n))))
    if n <= FULL_GMRES_SIZE:  # small systems: unrestarted GMRES (cannot stagnate)
        restart = max(restart, n)
    A = sys_.linear_operator()
    M = sys_.preconditioner() if precondition else None

    used = method
    message = ""
    residual = np.inf
    for _attempt in range(4):
        budget = maxiter - sys_.matvecs
        if budget <= 0:
            break
        with np.errstate(all="ignore"):
            if used == "cg":
                x, info = cg(A, b, x0=x, rtol=rtol, atol=0.0, maxiter=budget, M=M)
            elif used == "bicgstab":
                # two matvecs per iteration; at most a quarter of the budget, so that the
                # GMRES fallback (stagnation, breakdown) keeps three quarters (measured:
                # BiCGSTAB converges in ≤ 350 products where it converges at all on the
                # benchmark masks, a quarter of the guard is ≥ 500)
                x, info = bicgstab(A, b, x0=x, rtol=rtol, atol=0.0, maxiter=max(1, budget // 8),
                                   M=M)
            else:
                rs = max(1, min(restart, budget))  # never overshoot the guard
                x, info = gmres(A, b, x0=x, rtol=rtol, atol=0.0, restart=rs,
                                maxiter=max(1, budget // rs), M=M)
        if not np.all(np.isfinite(x)):
            x = np.zeros(n)
            message = f"{used} produced non-finite values"
            if used != "gmres" and not op.symmetric:
                used = "gmres"
                continue
            break
        residual = float(np.linalg.norm(b - A.matvec(x)) / bnorm)
        if residual <= TRUE_RESIDUAL_MARGIN * rtol:
            message = "converged"
            break
        if info < 0 or (used == "bicgstab" and info > 0):
            message = f"{used} stopped (info={info}), residual {residual:.2e}"
            if used == "bicgstab":
                used = "gmres"  # breakdown or stagnation: fall back
            continue
        message = f"{used}: residual {residual:.2e} above tolerance, restarting"
    converged = residual <= TRUE_RESIDUAL_MARGIN * rtol
    if not converged:
        message = (f"not converged after {sys_.matvecs} matvecs (guard {maxiter}): relative "
                   f"residual {residual:.3e} > {TRUE_RESIDUAL_MARGIN * rtol:.1e}; " + message)
    return SolveResult(sys_.expand(x), sys_.matvecs, residual, converged, message, used)
