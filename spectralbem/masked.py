"""Masked linear solves: given a contact mask A and the displacement on A, the pressure on A.

Solves ``(C p)_i = b_i`` for i ∈ A with ``p = 0`` off A (seed Eq. (15) on a grid).  C is the
:class:`~spectralbem.spectral.SpectralOperator`.

* Any operator (default): right-preconditioned GMRES with the Fourier
  preconditioner ``M = P F⁻¹[1/Ĉ] F P`` (docs/derivations.md §8), fused with the operator
  (:class:`PackedSystem`, :func:`fused_gmres`: two FFT pairs per product on the plan's own
  buffers, packed vectors of the mask); scipy's GMRES(m) (m = 300 where memory allows)
  takes over the rest of the guard if it stalls.  scipy's CG, BiCGSTAB and GMRES remain
  available (``method``).  The masked matrix P C P has a positive-definite symmetric part
  (Re 1/E > 0), so both are well posed.
* Warm starts through ``x0``.  An iteration guard (``maxiter`` matrix-vector products) always
  terminates; the returned :class:`SolveResult` states whether the *true* residual
  ``‖b - A x‖/‖b‖`` met the tolerance.

scipy's Krylov implementations work on the packed vector of mask values.
"""

from __future__ import annotations

import bisect
import functools
from dataclasses import dataclass

import numpy as np
from scipy.linalg.blas import dgemv
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


#: DGKS threshold: a second Gram–Schmidt pass when ‖w‖ drops below this fraction of itself
REORTHOGONALISE = 2**-0.5


class PackedSystem:
    """The right-preconditioned masked operator on the packed values of a contact set A.

    ``apply(v)`` returns Π (C P M̃ v)|_A with M̃ = Π (P F⁻¹[1/Ĉ] F P) Π, Π the mean removal
    on A under load control and the identity otherwise; ``precondition(v)`` returns M̃ v;
    ``transpose`` uses Cᵀ and its preconditioner (adjoint solves).
    Two FFT pairs per ``apply``; the transforms read and write the plan's own buffers, whose
    input stays zero off A for the whole solve (only A's cells are ever written).
    """

    def __init__(self, op: SpectralOperator, mask: np.ndarray, project: bool = False,
                 transpose: bool = False, idx: np.ndarray | None = None):
        self.op = op
        self.idx = np.flatnonzero(mask) if idx is None else idx  # idx: the caller's, shared
        self.n = self.idx.size
        self.project = project
        pl = op.plan
        self.pl = pl
        self.rin = pl.input_buffer.reshape(-1)
        self.rin[:] = 0.0
        # the transpose's multipliers are the conjugates: applied as conj(k · conj(X)), in
        # the plan's buffers, so that no conjugate copy is held during an adjoint solve
        self.k, self.kinv = op.multipliers()
        self.conj = transpose and op.viscoelastic
        self.pairs = 0

    def _transform(self, v: np.ndarray, k: np.ndarray) -> None:
        """F⁻¹[k] F P v into the plan's inverse buffer: one FFT pair."""
        self.pairs += 1
        pl = self.pl
        self.op.backend.scatter(self.rin, self.idx, v)
        spec = pl.spectrum_buffer
        if self.conj:
            np.conjugate(pl.forward_buffer(), out=spec)
            np.multiply(spec, k, out=spec)
            np.conjugate(spec, out=spec)
        else:
            np.multiply(pl.forward_buffer(), k, out=spec)

    def _gather(self) -> np.ndarray:
        """The last transform's values on A (a new packed array), projected."""
        out = self.op.backend.gather(self.pl.inverse_buffer().reshape(-1), self.idx)
        if self.project:
            out -= out.mean()
        return out

    def _pass(self, v: np.ndarray, k: np.ndarray) -> np.ndarray:
        """(F⁻¹[k] F P v)|_A, projected: one FFT pair."""
        self._transform(v, k)
        return self._gather()

    def precondition(self, v: np.ndarray) -> np.ndarray:
        return self._pass(v, self.kinv)

    def operator(self, v: np.ndarray) -> np.ndarray:
        """Π (C P v)|_A (no preconditioner): one pair."""
        return self._pass(v, self.k)

    def apply(self, v: np.ndarray) -> np.ndarray:
        t = self._pass(v, self.kinv)
        self._transform(t, self.k)
        del t  # the preconditioned vector is freed before the product is gathered
        return self._gather()


def fused_cg(system: PackedSystem, r0: np.ndarray, rtol: float, maxiter: int):
    """Preconditioned conjugate gradients for the correction x of ``A x = r0`` on a symmetric
    operator (C and the Fourier preconditioner symmetric positive definite on the set, and
    on its mean-free vectors under load control): two FFT pairs per iteration, O(1) vectors.
    Solves to the recursively updated ‖r‖ ≤ rtol·‖r0‖; returns (x, iterations, estimated
    relative residual) as :func:`fused_gmres`."""
    beta0 = float(np.linalg.norm(r0))
    x = np.zeros(r0.size)
    if beta0 == 0.0 or r0.size == 0:
        return x, 0, 0.0
    r = r0.copy()
    z = system.precondition(r)
    d = z.copy()
    rz = float(r @ z)
    used, rel = 0, 1.0
    while used < maxiter:
        q = system.operator(d)
        used += 1
        dq = float(d @ q)
        if not dq > 0:  # breakdown (round-off at convergence)
            break
        alpha = rz / dq
        x += alpha * d
        r -= alpha * q
        rel = float(np.linalg.norm(r)) / beta0
        if rel <= rtol:
            break
        z = system.precondition(r)
        rz, rz_old = float(r @ z), rz
        d *= rz / rz_old
        d += z
    return x, used, rel


#: rows of each block of the fused GMRES basis (products against it are BLAS 2 per block):
#: at most 3 unused rows allocated; the band solves of an adhesive state converge in 15-25
#: products, and with blocks of 8 the peak of the rough SLS state at 256² held 0.85 N²
#: arrays more (a first block of 33 held 8-18 vectors too many)
BASIS_BLOCK = 4


class _Basis:
    """The Arnoldi basis of :func:`fused_gmres`, in blocks of ``BASIS_BLOCK`` rows allocated
    as it grows: no block is ever copied (growing never holds an old and a new basis at
    once) and at most one block's rows are allocated beyond those in use."""

    def __init__(self, n: int, m: int):
        self.n, self.m = n, m
        self.blocks = [np.empty((min(m, BASIS_BLOCK) + 1, n))]
        self.starts = [0]

    def _block(self, k: int):
        i = bisect.bisect_right(self.starts, k) - 1  # (np.searchsorted converts the list)
        return self.blocks[i], k - self.starts[i]

    def row(self, k: int) -> np.ndarray:
        """Row k, to be written (a block is added when k is past the last one)."""
        end = self.starts[-1] + self.blocks[-1].shape[0]
        if k == end:
            self.starts.append(end)
            self.blocks.append(np.empty((min(BASIS_BLOCK, self.m + 1 - end), self.n)))
        b, i = self._block(k)
        return b[i]

    def _parts(self, k: int):
        """(block rows, offset) of the first k rows."""
        for b, s in zip(self.blocks, self.starts, strict=True):
            if s >= k:
                break
            yield b[: min(b.shape[0], k - s)], s

    def dot(self, k: int, w: np.ndarray) -> np.ndarray:
        """V[:k] w."""
        return np.concatenate([b @ w for b, _s in self._parts(k)])

    def subtract(self, k: int, w: np.ndarray, h: np.ndarray) -> None:
        """w −= V[:k]ᵀ h, in place (w: a contiguous float64 vector)."""
        for b, s in self._parts(k):
            _gemv_update(b, h[s: s + b.shape[0]], w, -1.0)

    def combine(self, k: int, y: np.ndarray) -> np.ndarray:
        """V[:k]ᵀ y."""
        out = np.zeros(self.n)
        for b, s in self._parts(k):
            _gemv_update(b, y[s: s + b.shape[0]], out, 1.0)
        return out


def _gemv_update(b: np.ndarray, x: np.ndarray, y: np.ndarray, alpha: float) -> None:
    """y += alpha·bᵀ x in place, one BLAS call (b: C-contiguous rows, so bᵀ is Fortran-ordered
    and not copied): half the time of ``y -= b.T @ x``, which forms bᵀ x in a temporary and
    subtracts it in a second pass (measured at 52 000 × 12: 0.33 ms against 0.69 ms); equal to
    it up to the order of the sums (rounding)."""
    r = dgemv(alpha, b.T, x, beta=1.0, y=y, overwrite_y=1)
    if r is not y:  # (f2py copies y only if it is not a contiguous float64 vector)
        y[...] = r


def _grown(H: np.ndarray, m: int) -> np.ndarray:
    """H copied into the top-left corner of a zero (m + 1) × m matrix."""
    G = np.zeros((m + 1, m))
    G[: H.shape[0], : H.shape[1]] = H
    return G


def fused_gmres(system: PackedSystem, r0: np.ndarray, rtol: float, maxiter: int,
                restart: int | None = None):
    """Right-preconditioned restarted GMRES for the correction x of ``A M x' = r0``, x = M x'.

    Solves to ‖r0 − A x‖ ≤ rtol·‖r0‖ (the Arnoldi estimate, exact in exact arithmetic) within
    ``maxiter`` operator applications.  Classical Gram–Schmidt, re-orthogonalised once where
    the first pass cancels more than 1 − 1/√2 of the vector (the criterion of Daniel, Gragg,
    Kaufman and Stewart): matrix-vector products against the basis, BLAS 2.  ``restart``:
    the restart length (None: ``RESTART_MAX`` as far as the basis fits in ``RESTART_BYTES``,
    at least 10).  Returns (x, applications, estimated relative residual).
    """
    n = r0.size
    beta0 = float(np.linalg.norm(r0))
    x = np.zeros(n)
    if beta0 == 0.0 or n == 0:
        return x, 0, 0.0
    m = int(max(10, min(RESTART_MAX, RESTART_BYTES // (8 * n) - 1)) if restart is None
            else max(1, restart))
    V = _Basis(n, m)  # grown as the iteration needs it
    H = np.zeros((min(m, 2 * BASIS_BLOCK) + 1, min(m, 2 * BASIS_BLOCK)))  # grown likewise
    cs, sn = np.zeros(m), np.zeros(m)
    r = r0  # never written in place: no copy (a restart binds a new residual)
    used = 0
    rel = 1.0
    while used < maxiter:
        beta = float(np.linalg.norm(r))
        rel = beta / beta0
        if rel <= rtol:
            break
        np.divide(r, beta, out=V.row(0))
        e = np.zeros(m + 1)
        e[0] = beta
        k = 0
        while k < m and used < maxiter:
            if k == H.shape[1]:  # the Hessenberg matrix doubles (it is (m + 1) × m at most)
                H = _grown(H, min(m, 2 * k))
            b, i = V._block(k)
            w = system.apply(b[i])
            used += 1
            wn = float(np.linalg.norm(w))
            h = V.dot(k + 1, w)
            V.subtract(k + 1, w, h)
            hn = float(np.linalg.norm(w))
            if hn < REORTHOGONALISE * wn:  # cancellation: re-orthogonalise once (DGKS)
                h2 = V.dot(k + 1, w)
                V.subtract(k + 1, w, h2)
                h += h2
                hn = float(np.linalg.norm(w))
            H[: k + 1, k] = h
            H[k + 1, k] = hn
            for j in range(k):  # apply the previous Givens rotations
                a, b = H[j, k], H[j + 1, k]
                H[j, k], H[j + 1, k] = cs[j] * a + sn[j] * b, -sn[j] * a + cs[j] * b
            d = np.hypot(H[k, k], H[k + 1, k])
            cs[k], sn[k] = (1.0, 0.0) if d == 0 else (H[k, k] / d, H[k + 1, k] / d)
            H[k, k], H[k + 1, k] = d, 0.0
            e[k], e[k + 1] = cs[k] * e[k], -sn[k] * e[k]
            k += 1
            rel = abs(e[k]) / beta0
            if hn == 0.0 or rel <= rtol:
                break
            np.divide(w, hn, out=V.row(k))  # w / hn, without a temporary
            w = None  # not held while the next product is formed
        w = None  # nor the last one through the update
        y = np.linalg.solve(np.triu(H[:k, :k]), e[:k]) if k else np.zeros(0)
        x += system.precondition(V.combine(k, y))
        if rel <= rtol or used >= maxiter:
            break
        r = r0 - system.operator(x)  # restart from the true residual (one pair)
    return x, used, rel


def solve_packed(op: SpectralOperator, mask: np.ndarray, p: np.ndarray, w: np.ndarray,
                 total: float | None, rtol: float, maxiter: int, forcing: float = 1.0):
    """Solve (C p)_A = (w + Δ)_A on the set A (p = 0 off A) from the warm start ``p`` by the
    fused preconditioned CG (symmetric C) or GMRES, to the relative residual ``rtol`` or
    ``forcing`` times the start's, whichever is smaller.

    ``total`` None: Δ = 0.  Otherwise Σ p = ``total`` and Δ is the unknown constant that
    allows it (a Lagrange multiplier, the mean of C p − w on A): the start is shifted on A
    to the sum, the correction is kept mean-free and the equations are projected on
    mean-free vectors (docs/derivations.md §8), one solve instead of two.  Returns (p,
    products, FFT pairs, estimated relative residual of the projected equations)."""
    load = total is not None
    sys_ = PackedSystem(op, mask, load)
    if sys_.n == 0:
        return np.zeros(p.shape), 0, 0, 0.0
    be = op.backend
    x0 = be.gather(p.reshape(-1), sys_.idx)
    if load:
        x0 += (total - x0.sum()) / sys_.n
    b = be.gather(w.reshape(-1), sys_.idx)
    if load:
        b = b - b.mean()
    r0 = b - sys_.operator(x0)
    # relative to the right-hand side; when it vanishes (a flat profile on A under load
    # control: the whole answer is the load's), relative to the start's residual
    bnorm = float(np.linalg.norm(b)) or float(np.linalg.norm(r0))
    rr = float(np.linalg.norm(r0)) / bnorm if bnorm > 0 else 0.0
    krylov = fused_cg if op.symmetric else fused_gmres
    x, used, rel = krylov(sys_, r0, min(rtol / max(rr, 1e-300), forcing), maxiter)
    out = np.zeros(p.size)
    be.scatter(out, sys_.idx, x0 + x)
    return out.reshape(p.shape), used, sys_.pairs, rel * rr


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
        self._mult = None  # (Ĉ, 1/Ĉ) or the transpose's, fetched on first use
        self.matvecs = 0

    def _multipliers(self):
        if self._mult is None:
            self._mult = self.op.multipliers(self.transpose)
        return self._mult

    @functools.cached_property
    def _full(self) -> np.ndarray:  # work arrays of scipy's solvers, allocated on first use
        return np.zeros(self.op.cell.shape)

    @functools.cached_property
    def _out(self) -> np.ndarray:
        return np.empty(self.op.cell.shape)

    def expand(self, x: np.ndarray) -> np.ndarray:
        full = np.zeros(self.op.cell.shape)
        full.flat[self.idx] = x
        return full

    def matvec(self, x: np.ndarray) -> np.ndarray:
        self.matvecs += 1
        self._full.flat[self.idx] = x
        self.op._apply(self._full, self._multipliers()[0], self._out)
        return self._out.flat[self.idx].copy()

    def precondition(self, x: np.ndarray) -> np.ndarray:
        self._full.flat[self.idx] = x
        self.op._apply(self._full, self._multipliers()[1], self._out)
        return self._out.flat[self.idx].copy()

    def linear_operator(self) -> LinearOperator:
        return LinearOperator((self.n, self.n), matvec=self.matvec, dtype=np.float64)

    def preconditioner(self) -> LinearOperator:
        return LinearOperator((self.n, self.n), matvec=self.precondition, dtype=np.float64)


#: GMRES restart length, as far as the basis fits in RESTART_BYTES (the fused GMRES grows
#: its basis as it iterates; measured in docs/performance.md, the masked solves)
RESTART_MAX = 300
RESTART_BYTES = 200 * 2**20

#: masks up to this many cells use unrestarted GMRES: measured on the sinusoid at β = 1e3,
#: ζ = 1 (≈100-cell masks) GMRES(60) stagnated at residual 1e-3 after 700 matvecs
FULL_GMRES_SIZE = 500


def _fused(op, mask, b, x, bnorm, rtol, maxiter, transpose, counter, restart=None):
    """The fused preconditioned solve (CG on a symmetric operator, else right-preconditioned
    GMRES, restarted after ``restart`` products when given) from the packed start ``x``:
    (x, true relative residual, message); its products (two FFT pairs each, plus the
    residual's pairs) are added to ``counter.matvecs``."""
    system = PackedSystem(op, mask, transpose=transpose, idx=counter.idx)
    r0 = b - system.operator(x)
    rr = float(np.linalg.norm(r0)) / bnorm
    if op.symmetric:
        dx, used, _rel = fused_cg(system, r0, rtol / max(rr, 1e-300), maxiter)
    else:
        dx, used, _rel = fused_gmres(system, r0, rtol / max(rr, 1e-300), maxiter, restart)
    x = x + dx
    residual = float(np.linalg.norm(b - system.operator(x))) / bnorm
    counter.matvecs += used + 1
    name = "CG" if op.symmetric else "GMRES"
    return x, residual, f"fused {name}: {used} products, residual {residual:.2e}"


def solve_masked(op: SpectralOperator, mask: np.ndarray, rhs: np.ndarray, *, x0=None,
                 x0_add=None, rtol: float = 1e-10, maxiter: int | None = None, method: str = "auto",
                 precondition: bool | None = None, transpose: bool = False,
                 restart: int | None = None) -> SolveResult:
    """Solve (C p)|_A = rhs|_A with p = 0 off A.

    Parameters
    ----------
    rhs : full-grid array; only its values on the mask are used.
    x0 : full-grid warm start (values on the mask are used).
    x0_add : (flat cells, values) added to the start on the cells of the mask among them (a
        correction kept packed: no full-grid copy of the start is made).
    rtol : relative tolerance on ‖b - A x‖/‖b‖.
    maxiter : guard on matrix-vector products (default 20·√n + 500).
    method : 'auto' (the fused GMRES of :class:`PackedSystem`, which hands what is left of
        the guard to scipy's GMRES(m) if it stalls; with ``precondition=False``, scipy's CG
        if symmetric, else BiCGSTAB), 'cg', 'bicgstab', 'gmres' (scipy, on
        :class:`MaskedSystem`) or 'fused'.
    precondition : Fourier preconditioner; default on for non-symmetric systems.
    transpose : solve with Cᵀ (adjoint solve).
    restart : the GMRES restart length of the fused solve and of scipy's; default
        ``RESTART_MAX`` (300) as far as its Krylov basis fits in ``RESTART_BYTES`` (200 MB),
        at least 60 for scipy's and 10 for the fused one.  Measured on the rough 256² mask
        at β = 1e4, ζ = 10: GMRES(60) needs 5894 products, GMRES(300) 1370 (the guard is
        2065).  A full basis can exceed the adhesive solve's memory budget of 25 N² arrays
        on mid-size grids (a 26k-cell mask at 512²: 63 MB, 30 arrays); only stagnating
        solves grow it that far (typical rough solves hold 20-60 vectors), which is why the
        cap is in bytes.
    """
    sys_ = MaskedSystem(op, mask, transpose=transpose)
    n = sys_.n
    shape = op.cell.shape
    if n == 0:
        return SolveResult(np.zeros(shape), 0, 0.0, True, "empty mask", "none")
    b = np.asarray(rhs, dtype=float).flat[sys_.idx].copy()
    del rhs  # the caller's temporary right-hand side is freed before the solve
    if not np.all(np.isfinite(b)):
        raise ValueError("rhs has non-finite values on the mask")
    bnorm = float(np.linalg.norm(b))
    if bnorm == 0.0:
        return SolveResult(np.zeros(shape), 0, 0.0, True, "zero right-hand side", "none")
    x = np.zeros(n) if x0 is None else np.asarray(x0, dtype=float).flat[sys_.idx].copy()
    if x0_add is not None:
        cells, values = x0_add
        pos = np.minimum(np.searchsorted(sys_.idx, cells), max(n - 1, 0))
        on = sys_.idx[pos] == cells
        x[pos[on]] += values[on]
        del cells, values, pos, on, x0_add  # not held through the solve
    if not np.all(np.isfinite(x)):
        x = np.zeros(n)
    if maxiter is None:
        maxiter = int(20 * np.sqrt(n) + 500)
    if method == "auto":
        # the fused solver is always preconditioned; on symmetric systems too it needs
        # fewer transforms than plain CG (elastic adhesive state at 256²: 922 products of
        # two pairs against 2432 CG iterations of one, 2.2 s against 3.0 s)
        method = ("fused" if precondition is not False
                  else "cg" if op.symmetric else "bicgstab")
    if method not in ("cg", "bicgstab", "gmres", "fused"):
        raise ValueError(
            f"method = {method!r}; allowed: 'auto', 'cg', 'bicgstab', 'gmres', 'fused'")
    if method == "fused":
        x, residual, message = _fused(op, mask, b, x, bnorm, rtol, maxiter, transpose, sys_,
                                      restart)
        if residual <= TRUE_RESIDUAL_MARGIN * rtol or sys_.matvecs >= maxiter:
            converged = residual <= TRUE_RESIDUAL_MARGIN * rtol
            if not converged:
                message = (f"not converged after {sys_.matvecs} products (guard {maxiter}): "
                           f"relative residual {residual:.3e} > "
                           f"{TRUE_RESIDUAL_MARGIN * rtol:.1e}; " + message)
            return SolveResult(sys_.expand(x), sys_.matvecs, residual, converged, message,
                               "fused")
        method = "gmres"  # the remaining budget to scipy's GMRES(m) (it restarts from x)
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
