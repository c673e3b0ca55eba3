"""Compiled inner loops: the Polonsky–Keer iteration (:func:`spectralbem.contact.polonsky_keer`)
and the 1D kernel table (:class:`spectralbem.sinusoid1d.Kernel1D`).

At 1024² and above one PK iteration is memory-bound outside its FFTs: numpy needs one full
pass per operation (a subtraction, a minimum, a mask, a product, ...).  These seven loops
read each array once.  They are compiled with numba (``cache=True``: the first use in a fresh
checkout compiles all seven in ~0.7 s, later processes load them in ~0.2 s); without numba, or with
``SPECTRALBEM_JIT=0``, the same functions run as numpy expressions (identical results up to
the summation order, slower).  ``backend()`` tells which is in use.

* :func:`parseval_sum` — ``Σ_q m_q k_q |T_q|²`` over a half spectrum (m_q the column
  multiplicity): ⟨C t, t⟩ by Parseval.
* :func:`spectrum_step` — ``P ← P + a·D`` and ``out = (s·k)·P`` in one pass (the pressure
  spectrum update and the kernel product that feeds the inverse transform).
* :func:`gap_scan` — the cells where ``u − w_out < level``, with ``w_out = −∞`` on the
  contact set (the overlap test of PK; no minimum and no mask test per cell: one compare
  per cell, a branch taken only at the rare overlaps).
* :func:`contact_gap` — on the contact set: the gap, its mean (load control) and the sums
  of the PK error and step, and ⟨g, t_old⟩ for the descent test.
* :func:`direction` — the conjugate direction, written into the FFT input as well.
* :func:`pk_step` — the packed pressure step ``pc − τ·tc``, its negative cells (listed) and
  ``Σ max(pc, 0)``.
* :func:`merge_set` — the new contact set: the cells with ``pc < 0`` dropped, the joining
  cells merged in (both index lists sorted), with their t, p and w.
* :func:`periodic_cubic` — the 1D method's viscoelastic kernel remainder: a periodic
  piecewise cubic evaluated at M × Q distances without temporaries (it was 70 % of a 1D
  solve at ζ = 1e-3 as numpy passes).
"""

from __future__ import annotations

import os

import numpy as np
from scipy.linalg.blas import zaxpy

_WANT_JIT = os.environ.get("SPECTRALBEM_JIT", "1").lower() not in ("0", "false", "no")

try:  # pragma: no cover - exercised through backend()
    if not _WANT_JIT:
        raise ImportError
    import numba
except ImportError:  # pragma: no cover
    numba = None


def backend() -> str:
    """'numba' or 'numpy'."""
    return "numba" if numba is not None else "numpy"


# -- numpy versions (the reference the compiled loops are tested against) ----------------------
def parseval_sum_numpy(T: np.ndarray, k: np.ndarray, m: np.ndarray) -> float:
    return float(np.sum(m * k * (T.real**2 + T.imag**2)))


def spectrum_step_numpy(P, D, a, k, s, out) -> None:
    r = zaxpy(D.reshape(-1), P.reshape(-1), a=a)  # in place when P is contiguous
    if not np.may_share_memory(r, P):
        P[...] = r.reshape(P.shape)
    np.multiply(P, k * s, out=out)


def gap_scan_numpy(u, w_out, level, out_index):
    ov = np.flatnonzero(u - w_out < level)
    out_index[: ov.size] = ov
    return int(ov.size)


def contact_gap_numpy(u, idx, wc, pc, tc, load, gc):
    np.subtract(u.take(idx), wc, out=gc)
    gbar = float(gc.mean()) if load else 0.0
    gc -= gbar
    return (gbar, float(np.dot(pc, np.abs(gc))), float(pc.sum()), float(np.dot(gc, gc)),
            float(np.dot(gc, tc)))


def direction_numpy(gc, tc, beta, load, rin, idx):
    tc *= beta
    tc += gc
    if load:
        tc -= tc.mean()
    rin.put(idx, tc)
    return float(np.dot(gc, tc))


def pk_step_numpy(pc_cur, tc, tau, clip_pos):
    pc = pc_cur - tau * tc
    neg = np.flatnonzero(pc < 0)
    clip_pos[: neg.size] = neg
    return pc, int(neg.size), float(np.maximum(pc, 0.0).sum())


def merge_set_numpy(idx, tc, pc, wc, ov, pov, w):
    keep = pc >= 0
    idx, tc, pc, wc = idx[keep], tc[keep], pc[keep], wc[keep]
    if ov.size:
        idx = np.concatenate([idx, ov])
        order = np.argsort(idx, kind="stable")
        idx = idx[order]
        tc = np.concatenate([tc, np.zeros(ov.size)])[order]
        pc = np.concatenate([pc, pov])[order]
        wc = np.concatenate([wc, w.take(ov)])[order]
    return idx, tc, pc, wc


def periodic_cubic_numpy(coefs, x, y, lam, inv_dx, guard, out, near_index):
    n = coefs.shape[0]
    d = np.subtract.outer(np.asarray(x, float), np.asarray(y, float)).ravel()
    if d.size and max(-d.min(), d.max()) >= lam:
        d = np.mod(d, lam)
    pos = d * inv_dx
    np.add(pos, n, out=pos, where=pos < 0)
    near = np.flatnonzero(np.abs(pos - 0.5 * n) > 0.5 * n - guard)
    i = np.minimum(pos.astype(np.intp), n - 1)
    t = pos - i
    c = coefs.take(i, axis=0)
    out.reshape(-1)[:] = c[:, 0] + t * (c[:, 1] + t * (c[:, 2] + t * c[:, 3]))
    near_index[: near.size] = near
    return int(near.size)


if numba is not None:
    _jit = numba.njit(cache=True, nogil=True)
    # a sum may be reassociated (vectorised): half the time of the in-order sum, measured
    # at 512²; the result differs from numpy's pairwise sum by rounding only
    _jit_sum = numba.njit(cache=True, nogil=True, fastmath={"reassoc", "contract"})

    @_jit_sum
    def _parseval_sum(T, k, m):  # pragma: no cover - compiled
        s = 0.0
        for i in range(T.shape[0]):
            for j in range(T.shape[1]):
                z = T[i, j]
                s += m[j] * k[i, j] * (z.real * z.real + z.imag * z.imag)
        return s

    @_jit
    def _spectrum_step(P, D, a, k, s, out):  # pragma: no cover - compiled
        for i in range(k.size):
            v = P[i] + a * D[i]
            P[i] = v
            out[i] = (s * k[i]) * v

    @_jit
    def _gap_scan(u, w_out, level, out_index):  # pragma: no cover - compiled
        n = 0
        for i in range(u.size):
            if u[i] - w_out[i] < level:
                out_index[n] = i
                n += 1
        return n

    @_jit
    def _contact_gap(u, idx, wc, pc, tc, load, gc):  # pragma: no cover - compiled
        n = idx.size
        s = 0.0
        for k in range(n):
            g = u[idx[k]] - wc[k]
            gc[k] = g
            s += g
        gbar = s / n if (load and n > 0) else 0.0
        e = 0.0
        ps = 0.0
        G = 0.0
        d = 0.0
        for k in range(n):
            g = gc[k] - gbar
            gc[k] = g
            e += pc[k] * abs(g)
            ps += pc[k]
            G += g * g
            d += g * tc[k]
        return gbar, e, ps, G, d

    @_jit
    def _direction(gc, tc, beta, load, rin, idx):  # pragma: no cover - compiled
        n = idx.size
        s = 0.0
        for k in range(n):
            t = gc[k] + beta * tc[k]
            tc[k] = t
            s += t
        m = s / n if (load and n > 0) else 0.0
        d = 0.0
        for k in range(n):
            t = tc[k] - m
            tc[k] = t
            rin[idx[k]] = t
            d += gc[k] * t
        return d

    @_jit
    def _pk_step(pc_cur, tc, tau, clip_pos):  # pragma: no cover - compiled
        pc = np.empty_like(pc_cur)
        nneg = 0
        total = 0.0
        for k in range(pc.size):
            v = pc_cur[k] - tau * tc[k]
            pc[k] = v
            if v < 0.0:
                clip_pos[nneg] = k
                nneg += 1
            else:
                total += v
        return pc, nneg, total

    @_jit
    def _merge_set(idx, tc, pc, wc, ov, pov, w):  # pragma: no cover - compiled
        m = ov.size
        for k in range(idx.size):
            if pc[k] >= 0.0:
                m += 1
        idx2 = np.empty(m, dtype=idx.dtype)
        tc2 = np.empty(m)
        pc2 = np.empty(m)
        wc2 = np.empty(m)
        i = 0
        j = 0
        o = 0
        while i < idx.size or j < ov.size:
            if i < idx.size and pc[i] < 0.0:
                i += 1
                continue
            if j < ov.size and (i >= idx.size or ov[j] < idx[i]):
                c = ov[j]
                tc2[o] = 0.0
                pc2[o] = pov[j]
                wc2[o] = w[c]  # only the joining cells read the full grid
                j += 1
            else:
                c = idx[i]
                tc2[o] = tc[i]
                pc2[o] = pc[i]
                wc2[o] = wc[i]
                i += 1
            idx2[o] = c
            o += 1
        return idx2, tc2, pc2, wc2

    def pk_step(pc_cur, tc, tau, clip_pos):
        """(pc = pc_cur − τ·tc as a new array, the number n of its negative cells,
        Σ max(pc, 0)); their positions in pc, increasing, go to ``clip_pos[:n]``."""
        pc, nneg, total = _pk_step(pc_cur, tc, float(tau), clip_pos)
        return pc, int(nneg), float(total)

    def merge_set(idx, tc, pc, wc, ov, pov, w):
        """The contact set after a step: the cells of ``idx`` with ``pc < 0`` dropped, the
        cells ``ov`` (sorted, disjoint from ``idx``) merged in with t = 0 and p = ``pov``;
        returns (idx, tc, pc, w[idx]), ``idx`` sorted (``wc`` = w[idx] on entry: only the
        joining cells are read from the full grid)."""
        return _merge_set(idx, tc, pc, wc, ov, pov, w)

    @_jit
    def _periodic_cubic(coefs, x, y, lam, inv_dx, guard, out, near_index):  # pragma: no cover
        n = coefs.shape[0]
        half = 0.5 * n
        cnt = 0
        for j in range(x.size):
            for i in range(y.size):
                d = x[j] - y[i]
                if d >= lam or d <= -lam:
                    d = d % lam  # Python's modulo: in [0, λ)
                pos = d * inv_dx
                if pos < 0.0:
                    pos += n
                if abs(pos - half) > half - guard:
                    near_index[cnt] = j * y.size + i
                    cnt += 1
                c = int(pos)
                if c > n - 1:
                    c = n - 1
                t = pos - c
                out[j, i] = coefs[c, 0] + t * (coefs[c, 1] + t * (coefs[c, 2]
                                                                  + t * coefs[c, 3]))
        return cnt

    def periodic_cubic(coefs, x, y, lam, inv_dx, guard, out, near_index):
        """The periodic piecewise cubic with rows ``coefs`` (c0..c3 per cell of width
        1/inv_dx, period λ) at the distances x_j − y_i, written to ``out`` (len(x) × len(y));
        the flat indices of the distances within ``guard`` cells of 0 (mod λ) go to
        ``near_index``, their number is returned."""
        return int(_periodic_cubic(coefs, np.ascontiguousarray(x, dtype=float),
                                   np.ascontiguousarray(y, dtype=float), float(lam),
                                   float(inv_dx), float(guard), out, near_index))

    def contact_gap(u, idx, wc, pc, tc, load, gc):
        """On the contact set ``idx``: gc = u[idx] − wc − ḡ (ḡ its mean under load control,
        else 0), written in place; returns (ḡ, Σ pc|gc|, Σ pc, Σ gc², Σ gc·tc) — the last
        for the descent test of the next direction."""
        return _contact_gap(u, idx, wc, pc, tc, bool(load), gc)

    def direction(gc, tc, beta, load, rin, idx):
        """tc ← gc + β·tc (mean-free under load control), in place, also written to
        ``rin[idx]``; returns ⟨gc, tc⟩."""
        return float(_direction(gc, tc, float(beta), bool(load), rin, idx))

    def parseval_sum(T: np.ndarray, k: np.ndarray, m: np.ndarray) -> float:
        """Σ m_j k_ij |T_ij|² for a complex half spectrum T, real k of the same shape and the
        column multiplicities m (length T.shape[1])."""
        return float(_parseval_sum(T, k, m))

    def spectrum_step(P, D, a, k, s, out) -> None:
        """P ← P + a·D (in place) and out = s·k·P, in one pass (contiguous arrays)."""
        if not (P.flags.c_contiguous and out.flags.c_contiguous):
            raise ValueError("spectrum_step needs C-contiguous P and out (updated in place)")
        _spectrum_step(P.reshape(-1), D.reshape(-1), float(a), k.reshape(-1), float(s),
                       out.reshape(-1))

    def gap_scan(u, w_out, level, out_index):
        """The number n of cells with u − w_out < level (``w_out`` = w outside the contact
        set, −∞ on it); their flat indices are written to ``out_index[:n]`` in increasing
        order."""
        return int(_gap_scan(u, w_out, float(level), out_index))
else:  # pragma: no cover - the numpy build
    parseval_sum = parseval_sum_numpy
    spectrum_step = spectrum_step_numpy
    gap_scan = gap_scan_numpy
    contact_gap = contact_gap_numpy
    direction = direction_numpy
    pk_step = pk_step_numpy
    merge_set = merge_set_numpy
    periodic_cubic = periodic_cubic_numpy
