"""Adhesiveless contact: non-penetration g ≥ 0, p ≥ 0, p·g = 0 (the seed's closure without
adhesion: σ = 0 at ∂Ω).

* Symmetric operator (elastic, or v = 0): Polonsky & Keer (1999) constrained conjugate
  gradients, under mean-pressure or penetration control.  The displacement is updated
  incrementally (u ← u - τ C t) and recomputed from p only when the active set changes, so a
  converging iteration costs one FFT pair.
* Viscoelastic steady sliding (non-symmetric C): active set on the contact mask with the masked
  Krylov solver of :mod:`spectralbem.masked` — cells with p < 0 leave, cells with g < 0 join —
  started from the elastic solution with the symmetric part of the kernel.  The LCP is uniquely
  solvable because P C P has a positive-definite symmetric part (docs/derivations.md §8).

Outputs (:class:`~spectralbem.state.ContactState`): pressure p (Pa), displacement u (m, into
the slab), gap g (m), contact mask, mean pressure p̄, penetration Δ (mean-level gauge for the
half-space), status, and the friction coefficient of seed Eq. (19) generalised to 2D
(:mod:`spectralbem.friction`)::

    μ = -(1/(A0 p̄)) ∫ p (v̂·∇h) d²x          (force component opposing the sliding)
    μ_⊥ = -(1/(A0 p̄)) ∫ p (v̂⊥·∇h) d²x       (lateral force, v̂⊥ = ẑ × v̂)

with the exact spectral gradient of the rigid profile, cross-checked by the spectral dissipation
form (docs/derivations.md §5).
"""

from __future__ import annotations

import math

import numpy as np

from .conventions import control, shown
from .fft import with_fft_threads_only
from .friction import friction
from .masked import solve_masked
from .spectral import SpectralOperator
from .state import ContactState, Solution, status_of

__all__ = ["solve_contact", "polonsky_keer", "active_set", "full_contact", "ContactError"]


class ContactError(ValueError):
    """Invalid control parameter for a contact solve."""


def _check_controls(heights, op, mean_pressure, penetration):
    h = np.asarray(heights, dtype=float)
    if h.shape != op.cell.shape:
        raise ContactError(f"heights have shape {h.shape}, the grid is {op.cell.shape}")
    if not np.all(np.isfinite(h)):
        raise ContactError("heights contain NaN or inf")
    name, v = control(mean_pressure, penetration, ContactError,
                      {"mean_pressure": "(0, inf)"})
    if name == "mean_pressure" and v <= 0:
        raise ContactError(
            f"mean_pressure = {shown(v)} must be > 0 for adhesiveless contact (allowed (0, inf))")
    if name == "penetration":
        check_penetration(op.layer, op.material.nu, h, [v])
    return h


def check_penetration(layer, nu: float, heights, values) -> None:
    """Raise :class:`ContactError` naming the first penetration of ``values`` that admits no
    equilibrium (and how many more do not), before any solve.

    When the slab's mean displacement is 0 — the q = 0 mode dropped (half-space, layer under
    uniform pressure, A.5) or an incompressible layer glued to a rigid plate — g = u - w ≥ 0
    needs mean(w) = mean(h) - max(h) + Δ < 0, i.e. Δ < max(h) - mean(h) (at equality the
    contact is full and the mean pressure undetermined).  A compressible glued layer has a
    finite q = 0 compliance (A.4) and accepts any Δ."""
    c0 = layer.q0_compliance(1.0, nu)
    if c0:  # None (mode dropped) and 0 (incompressible) bound Δ
        return
    h = np.asarray(heights, dtype=float)
    limit = float(h.max() - h.mean())
    bad = [v for v in values if not float(v) < limit]
    if bad:
        why = ("an incompressible layer glued to a rigid plate" if c0 == 0 else
               f"{type(layer).__name__}: the q = 0 mode is dropped")
        more = f" (and {len(bad) - 1} more values)" if len(bad) > 1 else ""
        raise ContactError(
            f"penetration = {shown(float(bad[0]))}{more} admits no equilibrium: the mean "
            f"displacement is 0 ({why}), so Δ must be < max(h) - mean(h) = {shown(limit)} "
            f"(allowed (-inf, {shown(limit)}))")


def full_contact(op, h, mean_pressure=None, penetration=None):
    """Exact full-contact solution: u = w everywhere, solved mode by mode."""
    cell = op.cell
    hmax = float(h.max())
    K = op.kernel
    c0 = K[0, 0].real
    if mean_pressure is None and c0 == 0:
        return None  # the half-space cannot reach full contact at an arbitrary Δ
    pl = op.plan
    H = pl.forward(h)
    P = pl.spectrum_buffer  # the inverse's input: the pressure spectrum is built in place
    P[...] = 0.0
    np.divide(H, K, out=P, where=K != 0)  # no boolean gathers (they cost 2 ms at 512²)
    n = cell.Nx * cell.Ny
    if mean_pressure is not None:
        # mean(w) = c0 p̄ fixes Δ (c0 = 0: the zero-mean gauge)
        P[0, 0] = mean_pressure * n
        delta = c0 * mean_pressure - float(h.mean()) + hmax
    else:
        delta = penetration
        P[0, 0] = (float(h.mean()) - hmax + delta) / c0 * n
    p = pl.inverse_buffer() / n
    return p, delta


#: most changed cells whose correction is summed directly, at 512² (docs/performance.md)
SPARSE_MAX = 16


def sparse_max(n_cells: int) -> int:
    """The direct-sum threshold for a grid of ``n_cells`` (see :data:`SPARSE_MAX`)."""
    return int(SPARSE_MAX * max(1.0, np.sqrt(n_cells / 512**2)))


#: kernel span max Ĉ / min Ĉ above which CG converges slowly (its rate degrades as √span;
#: a half-space at 2048²: 1.4e3; a layer under pressure of thickness 0.01 L at 256²: 4.4e6)
SPAN_SLOW = 1e5

#: a PK gradient whose RMS over the contact set lies below this fraction of the height range
#: is round-off: the conjugate direction built on it carries no information and the next
#: direction restarts (β = 0).  A contact set solved exactly (one cell under penetration
#: control: G ≈ 1e-35) that cells then join gave β = G/G_old ≈ 1e26, a direction of 3e8 on
#: that cell and a step of 3e-25: PK stalled for its 10 000 iterations (tests/test_contact.py)
GRADIENT_ROUNDOFF = 64 * float(np.finfo(float).eps)

#: contact fraction at which polonsky_keer checks for full contact (once)
FULL_CHECK = 0.9

#: FFT inputs of at least this size are rewritten whole every PK iteration (docs/performance.md)
REFILL_BYTES = 2**20


#: the outer-step guard of the non-symmetric solvers (semismooth Newton, active set): at most
#: this many, fewer when ``solver.max_iterations`` is smaller
OUTER_MAX = 200

#: iterations between two calls of a solve's ``progress(iteration, text)``
PROGRESS_EVERY = 10


def polonsky_keer(op: SpectralOperator, heights, *, mean_pressure=None, penetration=None,
                  tol: float = 1e-10, maxiter: int = 10000, p0=None, refresh: int = 50,
                  restart: str = "descent", progress=None):
    """Constrained CG of Polonsky & Keer (1999) for a symmetric operator.

    The pressure is carried in Fourier space as well (p̂ = S·P, the load-control rescaling
    folded into the scalar S): the step length uses Parseval, ⟨C t, t⟩ = Σ_q Ĉ |t̂|²/N, so an
    iteration costs one forward FFT (of the search direction t) and one inverse FFT
    (u = C p).  When the active set changes, the projection correction c (clipped cells,
    cells that join) enters the update p̂ ← p̂ − τ·D as D = FFT(t − c/τ): a second forward
    FFT, or, when at most :func:`sparse_max` cells change, T plus the direct sum over those
    cells (:meth:`~spectralbem.fft.RealFFT2.add_sparse`, no transform); p̂ is recomputed
    exactly every ``refresh`` iterations.
    Real-space work is done on packed index arrays of the contact set; the full-grid passes
    are the fused loops of :mod:`spectralbem.kernels`.  Under load control the search
    direction is kept mean-free on the contact (the mean-gap term of PK).  A full contact is
    recognised by its exact mode-by-mode solution (:func:`full_contact`, one transform
    pair), tried once the contact set covers :data:`FULL_CHECK` of the cells, or before the
    start when the kernel spans more than :data:`SPAN_SLOW`.

    One departure from PK (``restart="descent"``, the default): they restart the conjugate
    directions (β = 0) whenever cells join the contact (``restart="join"``); here β = G/G_old
    is kept across every change of the contact set and the direction is restarted only when
    it would not be a descent direction (⟨g, t⟩ ≤ 0, so the step length τ is always
    positive) or was built on a gradient of round-off size (:data:`GRADIENT_ROUNDOFF`).
    Same solutions, fewer iterations: `python bench/pk_restart.py`, table in
    docs/performance.md.

    The error is the complementarity ``Σ p|g| / (Σ p · (max h - min h))`` on the contact;
    convergence also requires no overlap (g < -tol·range where p = 0).

    Returns (p, u, delta, iterations, converged, message, fft_pairs).
    """
    if not op.symmetric:
        raise ContactError("polonsky_keer needs a symmetric operator (elastic or v = 0)")
    if restart not in ("descent", "join"):
        raise ContactError(f"restart = {restart!r} must be 'descent' or 'join'")
    restart_on_join = restart == "join"
    h = np.ascontiguousarray(_check_controls(heights, op, mean_pressure, penetration))
    if mean_pressure is None and float(penetration) <= 0:
        # max w = Δ ≤ 0: p = 0 satisfies g ≥ 0 (at Δ = 0 the summit touches with no force;
        # the iteration's error Σ p|g| / Σ p was 0/0 there: a crash or a round-off status)
        return untouched(op.cell, penetration)
    shape = op.cell.shape
    n = h.size
    hmax = float(h.max())
    hrange = max(float(h.max() - h.min()), np.finfo(float).tiny)
    load = mean_pressure is not None
    pl = op.plan
    loops = op.backend.loops  # the fused loops (spectralbem.kernels) of the operator's backend
    kn = np.ascontiguousarray(op.multipliers()[0].real)  # kernel with the 1/N of the inverse
    mult = np.ascontiguousarray(op.cell.rfft_weights()[0])  # Parseval column multiplicities
    k_sparse = sparse_max(n)
    refill = 8 * n >= REFILL_BYTES  # float64 FFT input
    # full contact: the exact mode-by-mode solution, when it is admissible (p ≥ 0), is the
    # answer.  Checked before any start is built when Ĉ spans many decades (thin layers
    # under pressure, A.5: CG from a partial start can stall there), else once the contact
    # set first covers FULL_CHECK of the cells (one transform pair that a partial contact
    # of smaller extent never pays)
    # (under penetration control a zero-mean layer has no full-contact solution at a
    # prescribed Δ: full_contact returns None there)
    check_full = load or kn[0, 0] != 0
    full = None
    if check_full and op.span > SPAN_SLOW:
        check_full = False
        full = full_contact(op, h, mean_pressure, penetration)
        if np.all(full[0] >= 0):
            return Solution(full[0], op.apply(full[0]), full[1], full[0] > 0, 0, True,
                            "full contact", fft_pairs=2.0)
    if load:
        target = float(mean_pressure)
        w = (h - hmax).ravel()
        # default start: a Winkler (bed-of-springs) guess, p ∝ (h − h̄)₊ — the cells above the
        # mean plane; 1-6 % fewer iterations than a uniform start on rough surfaces (same
        # solution; measured at 512² and 1024², p̄/E* = 4e-4…4e-2)
        p = np.maximum((h - h.mean()).ravel(), 0.0) if p0 is None else \
            np.maximum(np.ravel(p0).astype(float), 0.0)
        if not p.sum() > 0:
            p = np.full(n, target)
        p *= target * n / p.sum()
    else:
        w = (h - hmax + float(penetration)).ravel()
        if p0 is not None and np.any(np.ravel(p0) > 0):
            p = np.maximum(np.ravel(p0).astype(float), 0.0)
        else:  # start from the points that overlap the undeformed surface
            p = np.maximum(w, 0.0)
            if not np.any(p > 0):
                p[np.argmax(w)] = 1.0
            p *= hrange / max(float(op.apply(p.reshape(shape)).max()), 1e-300)
    # the start's pair, and the full-contact check's when it ran
    forwards = inverses = 1 if full is None else 2
    rin = pl.input_buffer.reshape(-1)  # zero outside the contact set between transforms
    spec = pl.spectrum_buffer

    def spectrum_of(field):
        nonlocal forwards
        forwards += 1
        rin[:] = field
        out = pl.forward_buffer().copy()
        rin[:] = 0.0
        return out

    def inverse():
        nonlocal inverses
        inverses += 1
        return pl.inverse_buffer().reshape(-1)  # u: overwritten by the next inverse

    P = spectrum_of(p)
    S = 1.0
    np.multiply(P, kn, out=spec)
    u = inverse()
    idx = np.flatnonzero(p > 0)
    w_out = w.copy()  # w outside the contact set, −∞ on it: the overlap scan's target
    w_out[idx] = -np.inf
    ov_buf = np.empty(n, dtype=np.intp)
    clip_buf = np.empty(n, dtype=np.intp)
    wc = w.take(idx)  # w and p on the contact set, kept in step with idx
    pc_cur = p.take(idx)
    tc = np.zeros(idx.size)
    gc = np.empty(idx.size)
    G_old = 0.0  # the first direction is the gradient (β = 0)
    G_floor = 0.0  # G_old at or below it is round-off (GRADIENT_ROUNDOFF): β = 0
    roundoff_per_cell = (GRADIENT_ROUNDOFF * hrange) ** 2
    c_self = None  # ⟨C δ, δ⟩, the self-compliance of a cell (a Jacobi step; computed once)
    err = np.inf
    gbar = 0.0
    message = f"not converged in {maxiter} iterations"
    converged = False
    it = 0
    for it in range(1, maxiter + 1):
        if check_full and idx.size >= FULL_CHECK * n:
            check_full = False
            u = u.copy()  # the check's transforms reuse the plan's buffers (u, rin)
            full = full_contact(op, h, mean_pressure, penetration)
            rin[:] = 0.0  # (direction writes rin on the contact set)
            forwards += 1
            inverses += 1
            if np.all(full[0] >= 0):
                return Solution(full[0], op.apply(full[0]), full[1], full[0] > 0, it - 1,
                                True, "full contact",
                                fft_pairs=0.5 * (forwards + inverses) + 1.0)
        if idx.size == 0:
            if load or float(penetration) > 0:  # max w = Δ > 0: the bodies overlap
                message = f"the contact set emptied at iteration {it} while the bodies overlap"
            else:
                message = "no contact: the indenter does not reach the surface"
                converged = True
            break
        # the gap on the contact set and the overlap scan of the other cells (the deepest
        # overlap, 0: none)
        gbar, e_sum, p_sum, G, g_t, t_mean, n_ov, overlap_min = loops.gap_state(
            u, idx, wc, pc_cur, tc, load, gc, w_out, ov_buf)
        # convergence test on the current state: complementarity and no overlap
        err = e_sum / (p_sum * hrange) if p_sum > 0 else math.inf  # no pressure left
        if progress is not None and it % PROGRESS_EVERY == 0:
            progress(it, f"error {err:.1e}")
        if not math.isfinite(err):
            message = f"non-finite error at iteration {it}"
            break
        if err < tol and overlap_min >= -tol * hrange:
            converged, message = True, "converged"
            break
        forwards += 1
        # Fletcher–Reeves β = G/G_old, kept across changes of the contact set; restarted (β = 0)
        # when the last gradient was round-off (G_floor) or t would not be a descent
        # direction: ⟨g, g + βt⟩ = G + β⟨g, t⟩ ≤ 0 (g is mean-free under load control, so t's
        # mean removal leaves the product unchanged)
        beta = G / G_old if G_old > G_floor else 0.0
        if not G + beta * g_t > 0:
            beta = 0.0
        if refill:  # the FFT input rewritten whole (see REFILL_BYTES)
            rin.fill(0.0)
        gc_tc = loops.direction(gc, tc, beta, t_mean, rin, idx)
        G_old = G
        G_floor = roundoff_per_cell * idx.size
        T = pl.forward_buffer()  # the plan's output buffer
        denom = loops.parseval_sum(T, kn, mult)  # ⟨C t, t⟩ by Parseval
        if denom > 0:
            tau = gc_tc / denom
        elif n_ov and G == 0.0:
            # the gradient vanishes on the contact set (one cell under load control: its
            # mean-free gap is 0) while other cells overlap: no conjugate step exists, the
            # overlapping cells join with a Jacobi step, τ = 1/C_ii (the self-compliance
            # ⟨C δ, δ⟩ = Σ_q Ĉ/N): each joins with the pressure that alone would lift its
            # overlap.  A spike (one cell above a flat surface) under load starts this way
            T.fill(0.0)  # t = 0: the direction's transform, for the correction below
            if c_self is None:
                c_self = loops.parseval_sum(np.ones_like(T), kn, mult)
            tau = 1.0 / c_self
            if not (math.isfinite(tau) and tau > 0):
                message = f"search direction degenerate at iteration {it} (error {err:.3e})"
                break
        else:
            message = f"search direction degenerate at iteration {it} (error {err:.3e})"
            break
        # pc = pc_cur − τ·tc; its negative cells are clipped; total = Σ max(pc, 0)
        pc, n_clip, total = loops.pk_step(pc_cur, tc, tau, clip_buf)
        if n_clip == pc.size and not n_ov and not load and float(penetration) > 0:
            # the step would clip every cell and empty the contact while the bodies overlap:
            # a direction of small ⟨C t, t⟩ (a near-uniform pressure on a kernel that holds
            # uniform loads weakly: an incompressible glued layer, Ĉ(0) = 0, under
            # penetration control) overshoots.  Shorten it to where half of the cells that t
            # unloads reach zero, and restart the directions (:func:`_emptying_step`)
            tau = _emptying_step(pc_cur, tc)
            pc, n_clip, total = loops.pk_step(pc_cur, tc, tau, clip_buf)
            G_old = 0.0
        ov = ov_buf[:n_ov]  # the joining cells (sorted)
        if restart_on_join and n_ov:
            G_old = 0.0  # PK (1999): the next direction is the gradient
        changed = n_clip > 0 or n_ov > 0
        recompute = it % refresh == 0  # p̂ from p below: no drift of the updates
        D = T
        if changed:
            # the projection correction c: c = −pc on clipped cells, the overlap-driven
            # pressure pov on joining cells; p̂ ← p̂ − τD with D = FFT(t − c/τ)
            cells, vals, pov, pov_sum = loops.corrections(
                idx, clip_buf[:n_clip], pc, tau, ov, u, w, gbar)
            total += pov_sum
            if not recompute and n_clip + n_ov <= k_sparse:
                pl.add_sparse(T, cells, vals)  # few cells: D = T + FFT(−c/τ), a direct sum
            elif not recompute:  # a second transform (rin holds t; t − c/τ = pc_cur/τ on a
                # clipped cell, u − w − ḡ on a joining one)
                rin.put(cells[:n_clip], pc_cur.take(clip_buf[:n_clip]) / tau)
                rin.put(ov, vals[n_clip:])
                forwards += 1
                D = pl.forward_buffer()
        scale = (target * n / total if total > 0 else math.nan) if load else 1.0
        if not (math.isfinite(scale) and scale > 0):
            message = f"pressure collapsed at iteration {it}: the load cannot be carried"
            break
        if changed:  # drop the clipped cells (pc < 0), merge the joining ones in, rescale
            idx, tc, pc, wc = loops.merge_set(idx, tc, pc, wc, ov, pov, w, scale, w_out, rin)
            gc = np.empty(idx.size)
        else:
            pc *= scale
        if recompute:  # p̂ = FFT(p): rin is zero outside the (new) contact set
            rin.put(idx, pc)
            forwards += 1
            np.copyto(P, pl.forward_buffer())
            S = 1.0
            np.multiply(P, kn, out=spec)
        else:
            loops.spectrum_step(P, D, -tau / S, kn, S * scale, spec)
            S *= scale
        u = inverse()
        pc_cur = pc
    else:
        message = f"not converged in {maxiter} iterations (error {err:.3e} > tol {tol:.1e})"
        if op.span > SPAN_SLOW:
            message += (f"; the kernel spans {op.span:.1e} (a thin {type(op.layer).__name__}?), "
                        "on which conjugate gradients converge slowly (docs/performance.md)")
    rin[:] = 0.0
    p[:] = 0.0
    p.put(idx, pc_cur)
    delta = gbar if load else float(penetration)
    pairs = 0.5 * (forwards + inverses)
    p = p.reshape(shape)
    return Solution(p, u.reshape(shape).copy(), delta, p > 0, it, converged, message,
                    fft_pairs=pairs)


def _emptying_step(pc: np.ndarray, tc: np.ndarray) -> float:
    """A step along ``tc`` that unloads the cells of pressure ``pc`` partly: the median, over
    the cells that ``tc`` unloads, of the step that brings each to zero (half of them clip)."""
    down = tc > 0
    return float(np.median(pc[down] / tc[down])) if down.any() else 0.0


def untouched(cell, penetration) -> Solution:
    """The state of a penetration Δ ≤ 0 (max w = Δ ≤ 0: p = 0 satisfies g ≥ 0)."""
    zero = np.zeros(cell.shape)
    return Solution(zero, zero.copy(), float(penetration), zero > 0, 0, True,
                    "no contact: the indenter does not reach the surface", fft_pairs=0.0)


#: outer iterations after which the active set moves only its worst offender per side
DAMP_AFTER = 30


def active_set(op: SpectralOperator, heights, *, mean_pressure=None, penetration=None,
               tol: float = 1e-10, max_outer: int = 200, mask0=None, p0=None):
    """Active-set LCP solver with masked Krylov solves (any operator, used when non-symmetric).

    ``iterations`` counts the Krylov products, ``outer_iterations`` the set updates.
    """
    h = _check_controls(heights, op, mean_pressure, penetration)
    cell = op.cell
    n = cell.Nx * cell.Ny
    hmax = float(h.max())
    hrange = max(float(h.max() - h.min()), np.finfo(float).tiny)
    load = mean_pressure is not None
    if not load and float(penetration) <= 0:
        return untouched(cell, penetration)
    if mask0 is None:
        # start from the solution of the relaxed elastic slab
        p_e = polonsky_keer(op.relaxed_part(), h, mean_pressure=mean_pressure,
                            penetration=penetration, tol=1e-6, maxiter=2000).pressure
        mask = p_e > 0
        p = p_e
    else:
        mask = np.asarray(mask0, dtype=bool).copy()
        p = np.zeros(cell.shape) if p0 is None else np.asarray(p0, float)
    if not np.any(mask):
        mask.flat[np.argmax(h)] = True
    seen = set()
    iterations = 0
    p1 = p2 = None
    delta = float(penetration) if not load else 0.0
    message = ""
    converged = False
    outer = 0
    for outer in range(1, max_outer + 1):
        if np.all(mask):
            full = full_contact(op, h, mean_pressure, penetration)
            if full is not None:
                p, delta = full
                if np.all(p >= 0):
                    converged, message = True, "full contact"
                    u = op.apply(p)
                    return Solution(p, u, delta, mask, iterations, converged, message,
                                    outer)
                mask = p > 0
                continue
        if load:
            # p = p1 + Δ p2 with C_AA p1 = (h - hmax)_A, C_AA p2 = 1_A, mean(p) = p̄
            r1 = solve_masked(op, mask, h - hmax, x0=p1, rtol=tol)
            r2 = solve_masked(op, mask, np.ones(cell.shape), x0=p2, rtol=tol)
            iterations += r1.iterations + r2.iterations
            if not (r1.converged and r2.converged):
                message = "masked solve: " + (r1.message if not r1.converged else r2.message)
                break
            p1, p2 = r1.field, r2.field
            s2 = float(p2.sum())
            if s2 == 0:
                message = "degenerate mask: unit-displacement solve has zero resultant"
                break
            delta_rel = (mean_pressure * n - float(p1.sum())) / s2
            p = p1 + delta_rel * p2
            delta = delta_rel
        else:
            w = h - hmax + delta
            res = solve_masked(op, mask, w, x0=p, rtol=tol)
            iterations += res.iterations
            if not res.converged:
                message = "masked solve: " + res.message
                break
            p = res.field
        u = op.apply(p)
        g = u - (h - hmax + delta)
        # both sides with a relative tolerance: round-off-sized violations at the edge would
        # otherwise flip one cell in and out for ever (measured at β = 1e3)
        remove = mask & (p < -tol * float(np.abs(p).max()))
        add = ~mask & (g < -tol * hrange)
        if not remove.any() and not add.any():
            converged, message = True, "converged"
            break
        key = hash(mask.tobytes())
        if key in seen or outer > DAMP_AFTER:
            # cycling (or wandering without an exact repeat, measured on the sinusoid at
            # β ≥ 1e3): move only the worst offenders
            if remove.any():
                worst = np.argmin(np.where(remove, p, np.inf))
                remove = np.zeros_like(mask)
                remove.flat[worst] = True
            if add.any():
                worst = np.argmin(np.where(add, g, np.inf))
                add = np.zeros_like(mask)
                add.flat[worst] = True
        seen.add(key)
        mask = (mask & ~remove) | add
        if not np.any(mask):
            message = "contact vanished: no cell carries compressive pressure"
            p = np.zeros(cell.shape)  # never a tensile pressure out of an adhesiveless solve
            break
    else:
        message = f"active set not converged in {max_outer} outer iterations"
    u = op.apply(p)
    return Solution(p, u, delta, mask, iterations, converged, message, outer)


@with_fft_threads_only
def solve_contact(op: SpectralOperator, heights, *, mean_pressure=None, penetration=None,
                  tol: float = 1e-10, maxiter: int = 10000, p0=None,
                  mask0=None, method: str = "auto", progress=None) -> ContactState:
    """Adhesiveless contact of the rigid profile ``heights`` under load or penetration control
    (the solver validates the inputs before any work).

    ``method``: 'auto' (Polonsky–Keer for a symmetric operator, the semismooth Newton method
    of :mod:`spectralbem.newton` otherwise, falling back to the active set where it does not
    converge), or 'active-set' (exact masked solves: the reference the Newton method is
    tested against, 3-100× slower); a symmetric operator always runs Polonsky–Keer.
    ``maxiter`` guards Polonsky–Keer's iterations, and the outer steps (Newton steps, set
    updates) of the other two, 200 at most.
    ``progress``: None or ``progress(iteration, text)``, called every
    :data:`PROGRESS_EVERY` iterations of Polonsky–Keer and at every Newton step."""
    from .newton import newton_contact

    if method not in ("auto", "active-set"):
        raise ContactError(f"method = {method!r}; allowed: 'auto', 'active-set'")
    h = np.asarray(heights, dtype=float)
    kw = dict(mean_pressure=mean_pressure, penetration=penetration, tol=tol, p0=p0)
    outer = min(OUTER_MAX, int(maxiter))  # the outer guard of the non-symmetric solvers
    if op.symmetric:
        r = polonsky_keer(op, h, maxiter=maxiter, progress=progress, **kw)
        method = "polonsky-keer"
        diag = {"fft_pairs": r.fft_pairs}
    elif method == "active-set":
        r = active_set(op, h, mask0=mask0, max_outer=outer, **kw)
        diag = {"outer_iterations": r.outer_iterations}
    else:
        r = newton_contact(op, h, mask0=mask0, progress=progress, max_outer=outer, **kw)
        method = "semismooth-newton"
        diag = {"outer_iterations": r.outer_iterations, "fft_pairs": r.fft_pairs}
        if not r.converged:
            # the exact-solve active set, from its own start: slower, but it converges on
            # some cases where the Newton steps wander (measured: β = 100, ζ = 1 on the
            # rough 128² surface of `bench/viscoelastic.py --robustness`)
            first = r
            r = active_set(op, h, mean_pressure=mean_pressure, penetration=penetration,
                           tol=tol, max_outer=outer)
            r = r._replace(iterations=r.iterations + first.iterations,
                           message=f"{r.message} (after the semismooth Newton method: "
                                   f"{first.message})")
            method = "active-set"
            diag.update(fallback_outer_iterations=r.outer_iterations)
    p, u, conv, msg = r.pressure, r.displacement, r.converged, r.message
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(u))):
        conv = False
        msg = "non-finite pressure or displacement: " + msg
        p = np.nan_to_num(p)
        u = np.nan_to_num(u)
    gap = u - (h - float(h.max()) + r.penetration)
    gap[r.contact] = 0.0
    return ContactState(
        pressure=p, displacement=u, gap=gap, contact=r.contact, penetration=float(r.penetration),
        mean_pressure=float(p.mean()), status=status_of(conv, r.contact),
        iterations=int(r.iterations), converged=bool(conv), message=msg, method=method,
        **friction(op, h, p, u), diagnostics=diag)
