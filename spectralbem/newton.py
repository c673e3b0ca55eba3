"""Non-symmetric adhesiveless contact (viscoelastic steady sliding): an inexact semismooth
Newton method on the contact set, preconditioned by the Fourier inverse of the kernel.

The problem is the linear complementarity problem of seed Eq. (15) on the grid: p ≥ 0,
g = C p − w − Δ ≥ 0, p·g = 0, with C = C^E + C^O non-symmetric (docs/derivations.md §8: the
masked matrix P C P has a positive-definite symmetric part, so the problem has one solution).
Newton's method on the semismooth equation min(p, g) = 0 is the primal-dual active-set
method: on the current contact set A solve (C p)_A = (w + Δ)_A with p = 0 off A, drop the
cells of A where p < 0, add the cells off A where g < 0, repeat until the set stops moving.
What makes it cheap:

* **the start**: Polonsky–Keer on the symmetric kernel |Ĉ| (the compliance 1/|E(q·v)|, the
  effective slab of contact-area theories of sliding rubber), to a loose tolerance: one FFT
  pair per iteration, and a contact set within ~10 % of the final one (measured on rough
  surfaces: |Ĉ| needs 20-25 % fewer transforms in all than the even part Re Ĉ, whose set
  is too small, and than the relaxed E0, whose set is too large; docs/performance.md);
* **inexact solves**: while the set is still moving, each masked solve stops at the relative
  residual ``LOOSE`` (1e-3), or a tenth of its starting residual if that is lower: enough
  to tell which cells leave or join; once the set has stopped moving the tolerance tightens
  (×1e-3, then the requested one) and the set is checked again;
* **one Krylov solve per Newton step, at two FFT pairs per iteration**: right-preconditioned
  GMRES on the packed values of the set, the preconditioner P F⁻¹[1/Ĉ] F P fused with the
  operator (the preconditioned field is masked in place between the two pairs, no full-grid
  copies); under load control the unknown Δ is eliminated by projecting the equations and the
  correction on the mean-free vectors of A (Π = I − 11ᵀ/|A|), so load control costs one solve,
  not two; the displacement that checks the set (u = C p, one pair) also gives the true
  residual of the solve.

docs/performance.md compares the candidates: this method, the active set with exact solves
(:func:`spectralbem.contact.active_set`), and splitting the odd part off (PK on C^E with
C^O p lagged), which diverges once the loss tangent exceeds 1.
"""

from __future__ import annotations

import numpy as np

from .masked import solve_packed
from .spectral import SpectralOperator
from .state import Solution

#: relative residual of the masked solves while the contact set still moves
LOOSE = 1e-3

#: every solve on a changed set reduces its starting residual at least by this factor (so
#: that a change of the set is always followed by a step of p, even when the residual is
#: already below the tolerance: without it, sets were seen to flip back and forth unsolved)
FORCING = 0.1

#: complementarity tolerance of the symmetric (|Ĉ|) start
START_TOL = 1e-3

#: iterations of the |Ĉ| start before it gives way to the relaxed elastic start
START_MAXITER = 300

#: outer iterations after which the set moves only its worst offender per side
#: (docs/performance.md, the Newton method)
DAMP_AFTER = 30

#: factor by which the solve tolerance tightens once the set stops moving (or moves no less
#: than STALL times as many cells as at the previous step)
LADDER = 1e-3
STALL = 0.5
#: ... when the set moves no more than this many cells (docs/performance.md)
STALL_CELLS = 32


def _gap(op, p, w, mask, load):
    """u = C p, the gap g = u − w − Δ (Δ: the mean of u − w on the set under load control),
    Δ and the true relative residual ‖g_A‖/‖(w − w̄)_A‖ of the masked equations."""
    u = op.apply(p)
    r = u - w
    shift = float(r[mask].mean()) if load else 0.0
    g = r - shift
    scale = float(np.linalg.norm(w[mask] - (w[mask].mean() if load else 0.0)))
    return u, g, shift, (float(np.linalg.norm(g[mask])) / scale if scale > 0 else 0.0)


def _worst(cells: np.ndarray, value: np.ndarray) -> np.ndarray:
    """Only the cell of ``cells`` with the most negative ``value`` (damped step)."""
    if not cells.any():
        return cells
    one = np.zeros_like(cells)
    one.flat[np.argmin(np.where(cells, value, np.inf))] = True
    return one


def _tighten(eta: float, tol: float) -> float:
    return tol if eta * LADDER < 100 * tol else eta * LADDER


def _start(op, h, mean_pressure, penetration, tol):
    """The start: PK on the kernel |Ĉ|, or, where that kernel stalls CG (it jumps across
    q_x = 0 at high ζ: the modes with q·v = 0 are relaxed, the others glassy; measured with
    Re Ĉ on a thin layer under pressure, 2000 iterations without converging), PK on the
    relaxed elastic kernel (E0).  Returns (p, FFT pairs)."""
    from .contact import polonsky_keer

    kw = dict(mean_pressure=mean_pressure, penetration=penetration, tol=tol)
    s = polonsky_keer(op.magnitude_part(), h, maxiter=START_MAXITER, **kw)
    p, pairs = s.pressure, s.fft_pairs
    if not s.converged:
        s = polonsky_keer(op.relaxed_part(), h, maxiter=2000, **kw)
        p, pairs = s.pressure, pairs + s.fft_pairs
    return p, pairs


def newton_contact(op: SpectralOperator, heights, *, mean_pressure=None, penetration=None,
                   tol: float = 1e-10, max_outer: int = 200, mask0=None, p0=None,
                   loose: float = LOOSE, start_tol: float = START_TOL, progress=None):
    """Adhesiveless contact of a non-symmetric operator by inexact semismooth Newton.

    Converged when no cell leaves or joins the set after a solve to ``tol`` (relative
    residual of the masked equations, checked on the true displacement) — the same criterion
    and thresholds as :func:`spectralbem.contact.active_set`.  Returns a
    :class:`~spectralbem.state.Solution`: ``iterations`` counts operator applications of the
    Krylov solves.
    """
    from .contact import _check_controls, full_contact, untouched

    h = _check_controls(heights, op, mean_pressure, penetration)
    cell = op.cell
    n = h.size
    hmax = float(h.max())
    hrange = max(float(h.max() - h.min()), np.finfo(float).tiny)
    load = mean_pressure is not None
    if not load and float(penetration) <= 0:
        return untouched(cell, penetration)
    pairs = 0.0
    if mask0 is None:
        p, start_pairs = _start(op, h, mean_pressure, penetration, start_tol)
        pairs += start_pairs
        mask = p > 0
    else:
        mask = np.asarray(mask0, dtype=bool).copy()
        p = np.zeros(cell.shape) if p0 is None else np.where(mask, np.asarray(p0, float), 0.0)
    if not np.any(mask):
        mask.flat[np.argmax(h)] = True
    w = h - hmax if load else h - hmax + float(penetration)
    target = float(mean_pressure) * n if load else 0.0
    delta = 0.0 if load else float(penetration)
    seen: set = set()
    last_changes = np.inf
    iterations = 0
    eta = max(loose, tol)
    converged, message = False, ""
    outer = 0
    u = None
    moved = True
    for outer in range(1, max_outer + 1):
        if progress is not None:
            progress(outer, f"Newton step, {int(mask.sum())} cells in contact")
        if np.all(mask):
            full = full_contact(op, h, mean_pressure, penetration)
            if full is not None:
                p, delta = full
                pairs += 1
                if np.all(p >= 0):
                    return Solution(p, op.apply(p), delta, mask, iterations, True,
                                    "full contact", outer, pairs + 1)
                mask = p > 0
                continue
        guard = int(20 * np.sqrt(np.count_nonzero(mask)) + 500)
        p, used, pp, rel = solve_packed(op, mask, p, w, target if load else None, eta, guard,
                                         FORCING if moved else 1.0)
        iterations += used
        pairs += pp + 1
        u, g, shift, true_rel = _gap(op, p, w, mask, load)
        if load:
            delta = shift
        if used >= guard and rel > eta:
            message = (f"masked solve not converged after {used} products (guard {guard}): "
                       f"relative residual {rel:.3e} > {eta:.1e}")
            break
        pmax = float(np.abs(p).max())
        remove = mask & (p < -tol * pmax)
        add = ~mask & (g < -tol * hrange)
        if not remove.any() and not add.any():
            if eta <= tol and true_rel <= 10 * tol:
                converged, message = True, "converged"
                break
            eta = _tighten(eta, tol)  # the set has stopped moving: tighten, check again
            moved = False
            continue
        changes = int(np.count_nonzero(remove) + np.count_nonzero(add))
        if changes > STALL * last_changes and changes <= STALL_CELLS and eta > tol:
            # the set stopped converging: the loose solves are too coarse to tell the cells
            # at its edge apart (measured: ±10 cells flipping for 100 outer steps at β = 100)
            eta = _tighten(eta, tol)
        last_changes = changes
        key = hash(mask.tobytes())
        if key in seen and eta > tol:
            eta = tol  # a repeated set under inexact solves: solve exactly before damping
        elif key in seen or outer > DAMP_AFTER:
            remove, add = _worst(remove, p), _worst(add, g)
        seen.add(key)
        if not np.any(mask & ~remove) and not add.any():
            if np.all(p <= 0):
                message = "contact vanished: no cell carries compressive pressure"
                p = np.zeros(cell.shape)
                u = np.zeros(cell.shape)
                break
            remove.flat[np.argmax(p)] = False  # an inexact step never empties the set
        mask = (mask & ~remove) | add
        p = np.where(mask, p, 0.0)
        moved = True
    else:
        message = f"semismooth Newton not converged in {max_outer} outer iterations"
    if u is None:
        u = op.apply(p)
    return Solution(p, u, delta, mask, iterations, converged, message, outer, pairs)
