"""The adjoint split of the work of the internal stresses δL_P (Eq. 10) over the cells of the
front tests' bands (docs/derivations.md §11): what the release rates G, G1, G2 and μ_a of a
state need (:func:`spectralbem.front.release_rates`), filled once, for the final state."""

from __future__ import annotations

import numpy as np

from .along_front import front_average
from .masked import solve_masked
from .spectral import SpectralOperator

__all__ = ["complete_adjoint", "adjoint_weights"]

#: restart length of the GMRES of the adjoint split's solves (the transposed solves and the
#: opening bands' states of :func:`complete_adjoint`): their Krylov basis comes on top of
#: the final state's fields, where a viscoelastic adhesive solve's memory peaks; the
#: transposed solves of the rough SLS state at 256² take 31-33 products at restarts of 8,
#: 12 or 16 against 29 unrestarted, with δL_P within 1e-10 (docs/performance.md, memory)
ADJOINT_RESTART = 8
#: products the restarted solve may take before the unrestarted one goes on from its answer
#: (a strongly non-symmetric kernel can stall a short restart)
ADJOINT_RESTART_GUARD = 200


def complete_adjoint(tests, op: SpectralOperator, mask: np.ndarray, p: np.ndarray,
                     rtol: float = 1e-10, starts=None):
    """Fill the adjoint split of δL_P (Eq. 10) over the band cells of ``tests`` (made on
    ``mask`` with its solution ``p``) in place and return ``tests`` (a no-op once filled).
    ``starts``: the :class:`~spectralbem.band_starts.BandStarts` of the solve that made
    ``tests``, whose corrections of the opening bands are those tests' own: each opening
    band's state A ∖ R starts from p plus its correction (float32: a few products to the
    tolerance instead of a solve from p).  (The transposed solves take as many products
    from A's adjoint solution as from zero: 33 against 34 on the rough SLS state at 256²,
    so they start from zero.)

    Closing bands: δL_P,j = a p_j(A ∪ D) ψ_j with ψ the adjoint weights of A
    (:func:`adjoint_weights`, one transposed solve); the rate δL_P/δA and G_close =
    (δL − δL_P)/δA of each outer front cell.  Opening bands: opening R is the closure of R
    from A ∖ R, so δL_P,j = a p_j(A) ψ'_j with ψ' the weights of A ∖ R (one solve for its
    pressure and one transposed solve per opening test); the rate of each inner front cell
    (``dLP_rate_in``), with which the release rate is interpolated to the balanced edge
    (front.release_rates).  An elastic scene has δL_P ≡ 0: no solve."""
    pend = tests.pending
    if pend is None:
        return tests
    visco = bool(op.viscoelastic)
    a = op.cell.cell_area
    b = tests.bands
    ob, ib = np.flatnonzero(b.outer_band), np.flatnonzero(b.inner_band)
    dLP_out, dLP_in = np.zeros(ob.size), np.zeros(ib.size)
    tests.rate = np.full(mask.shape, np.nan)
    weights = []  # (owners, band areas): the weights of the average along the front
    g_idx, g_val = [], []
    psi = None
    if visco and pend["close"]:
        psi = adjoint_weights(op, mask, p, rtol).ravel()
        tests.solves += 1
    own = tests.bands.outer_owner.ravel()
    for owners, bands_, dg_area, area in pend["close"]:
        dLP = np.zeros(owners.size)
        for cells, wt, apD in bands_ if psi is not None else ():
            dLPj = apD * psi[cells]
            dLP_out[np.searchsorted(ob, cells)] += wt * dLPj
            dLP += _owner_bincount(wt * dLPj, own[cells], owners)
        g_idx.append(owners)
        g_val.append(dg_area / area)  # each owner's mean Δγ
        tests.rate.ravel()[owners] = dLP / area
        weights.append((owners, area))
    del psi  # freed before the opening bands' solves
    g_idx = np.concatenate(g_idx or [np.zeros(0, int)])
    g_val = np.concatenate(g_val or [np.zeros(0)])
    if visco:
        tests.rate_in = True
        own = tests.bands.inner_owner.ravel()
        for owners, bands_, area in pend["open"]:
            dLP = np.zeros(owners.size)
            for cells, wt, key in bands_:
                rest = mask.copy()
                rest.ravel()[cells] = False
                if not rest.any():  # opening detaches: no stress, no work of any kind
                    continue
                res = _short_solve(op, rest, lambda: pend["w"], p, rtol,
                                   x0_add=None if starts is None else starts.start(key))
                tests.solves += 1
                if not res.converged:  # no split: the closing band's rate alone (nan here)
                    dLP[:] = np.nan
                    break
                psi_r = adjoint_weights(op, rest, res.field, rtol).ravel()
                del res  # each band's fields are freed before the next band's solves
                tests.solves += 1
                dLPj = a * p.ravel()[cells] * psi_r[cells]
                del psi_r
                dLP_in[np.searchsorted(ib, cells)] += wt * dLPj
                dLP += _owner_bincount(wt * dLPj, own[cells], owners)
            tests.rate.ravel()[owners] = dLP / area
            weights.append((owners, area))
    pend["w"] = None  # the prescribed w, needed by the opening solves only: freed here
    _average_rates(tests, weights)
    # G_close = δL/δA − δL_P/δA, both ratios of sums along the front: the balance F is
    # Σ δL / Σ Δγ a − 1 averaged so, δL/δA = Δγ (1 + F)
    tests.g_close = (g_idx, g_val * (1.0 + tests.F.ravel()[g_idx]) - tests.rate.ravel()[g_idx])
    tests.dLP_band = (dLP_out, dLP_in)
    tests.pending = None
    return tests


def _average_rates(tests, weights) -> None:
    """δL_P/δA of each front cell (``tests.rate``, in place) as a ratio of sums along the
    front — Σ δL_P / Σ δA over the front cells within the average's σ, the balance's
    average (``along_front.front_average``) — in place of the per-owner ratios, whose plain
    mean along a curved front is biased: a staircase corner owns a fan of band cells
    reaching a0 deep, the cells of a flat run only shallow rows (docs/theory.md, "Release
    rates along the front").  ``weights``: (owners, band areas) of each test.  Tests
    without an average along the front keep the per-owner ratios."""
    if tests.smoothing is None:
        return
    sigma, per_radius = tests.smoothing
    valid = np.isfinite(tests.rate)
    cells = np.concatenate([o for o, _ in weights] or [np.zeros(0, int)])
    area = np.concatenate([a for _, a in weights] or [np.zeros(0)])
    order = np.argsort(cells, kind="stable")
    cells, area = cells[order], area[order]
    area[~valid.ravel()[cells]] = 0.0
    # the weights packed on the owners: no N² array of them
    front_average(tests.bands, tests.rate, (cells, area), sigma, per_radius)
    tests.rate[~valid] = np.nan  # an owner whose split failed stays unknown


def _owner_bincount(values, owner, owners):
    """Σ values per entry of the sorted ``owners`` (cells whose owner is not listed: none)."""
    slot = np.searchsorted(owners, owner)
    slot = np.minimum(slot, owners.size - 1)
    keep = owners[slot] == owner
    return np.bincount(slot[keep], weights=values[keep], minlength=owners.size)


def _short_solve(op, mask, make_rhs, x0, rtol, transpose=False, x0_add=None):
    """The masked solve of the right-hand side ``make_rhs()`` from ``x0`` (plus ``x0_add``:
    masked.solve_masked's) restarted every :data:`ADJOINT_RESTART` products, within
    :data:`ADJOINT_RESTART_GUARD` of them; the unrestarted solve goes on from its answer if
    it stalls (the right-hand side, a temporary freed once packed, is formed again for it)."""
    res = solve_masked(op, mask, make_rhs(), x0=x0, x0_add=x0_add, rtol=rtol,
                       transpose=transpose, restart=ADJOINT_RESTART,
                       maxiter=ADJOINT_RESTART_GUARD)
    if res.converged:
        return res
    x0 = res.field
    del res
    return solve_masked(op, mask, make_rhs(), x0=x0, rtol=rtol, transpose=transpose)


def adjoint_weights(op: SpectralOperator, mask: np.ndarray, p: np.ndarray,
                    rtol: float = 1e-10) -> np.ndarray:
    """ψ = -C^O p - Cᵀ λ̃ with C_AAᵀ λ = (-C^O p)|_A (one transposed masked solve).

    For any closure A → A ∪ D at fixed Δ, Eq. (10) splits exactly into cells:
    δL_P = a Σ_{j∈D} p_j(A ∪ D) ψ_j (docs/derivations.md §11), whatever D is.
    """
    # the right-hand side is a temporary the solve frees once packed, and is formed again
    # after it (one FFT pair): no N² array of it is held while the Krylov basis grows
    res = _short_solve(op, mask, lambda: -op.apply_odd(p), None, rtol, transpose=True)
    t = op.apply_transpose(res.field)
    del res
    r = -op.apply_odd(p)
    r -= t
    return r
