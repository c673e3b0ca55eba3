"""Compiled inner loops: the Polonsky–Keer iteration (:func:`spectralbem.contact.polonsky_keer`),
the average along a contact front and the 1D kernel table
(:class:`spectralbem.oned.kernel.Kernel1D`).

Outside its FFTs one PK iteration is memory-bound: numpy needs one full pass per operation
(a subtraction, a minimum, a mask, a product, ...) and a Python call for each.  These loops
read each array once, and fuse what one iteration does between two transforms into a few
calls.  They are compiled with numba (``cache=True``: the first use in a fresh checkout
compiles them in ~1 s, later processes load them in ~0.2 s); without numba, or with
``SPECTRALBEM_JIT=0``, the same functions run as numpy expressions (identical results up to
the summation order, slower).  ``backend()`` tells which is in use.

* :func:`gap_state` — after the inverse transform: on the contact set the gap, its mean
  (load control), the sums of the PK error and step and ⟨g, t_old⟩ for the descent test; on
  the other cells the overlap scan ``u − w_out < ḡ`` (``w_out = −∞`` on the contact set:
  one compare per cell, counted block by block so that the count vectorises, the cells
  listed only in the rare blocks that have one).
* :func:`direction` — the conjugate direction, written into the FFT input as well.
* :func:`parseval_sum` — ``Σ_q m_q k_q |T_q|²`` over a half spectrum (m_q the column
  multiplicity): ⟨C t, t⟩ by Parseval.
* :func:`pk_step` — the packed pressure step ``pc − τ·tc``, its negative cells (listed) and
  ``Σ max(pc, 0)``.
* :func:`corrections` — the projection correction of a step that changes the contact set
  (clipped and joining cells), listed for the direct sum.
* :func:`merge_set` — the new contact set: the cells with ``pc < 0`` dropped, the joining
  cells merged in (both index lists sorted), with their t, p and w, the load rescaling
  applied, the full-grid arrays (``w_out``, the FFT input) updated where cells changed.
* :func:`spectrum_step` — ``P ← P + a·D`` and ``out = (s·k)·P`` in one pass (the pressure
  spectrum update and the kernel product that feeds the inverse transform).
* :func:`front_walk` — the lazy random walk that averages the energy balance along a
  contact front (:mod:`spectralbem.along_front`): each front cell's row of the walk's CSR
  matrix applied 2σ² times, all patches' σ groups in one call (as scipy sparse products,
  one Python call per step and group, it was a quarter of the 512² elastic adhesive state).
* :func:`scatter` — packed values written into a flat field (the masked solves' Krylov
  products; ``ndarray.put`` has no fast path for it).
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


def gap_state_numpy(u, idx, wc, pc, tc, load, gc, w_out, ov_buf):
    np.subtract(u.take(idx), wc, out=gc)
    gbar = float(gc.mean()) if (load and gc.size) else 0.0
    gc -= gbar
    t_mean = float(tc.mean()) if (load and tc.size) else 0.0
    d = u - w_out
    ov = np.flatnonzero(d < gbar)
    ov_buf[: ov.size] = ov
    ov_min = float(d[ov].min()) - gbar if ov.size else 0.0
    return (gbar, float(np.dot(pc, np.abs(gc))), float(pc.sum()), float(np.dot(gc, gc)),
            float(np.dot(gc, tc)), t_mean, int(ov.size), ov_min)


def direction_numpy(gc, tc, beta, shift, rin, idx):
    tc -= shift
    tc *= beta
    tc += gc
    rin.put(idx, tc)
    return float(np.dot(gc, tc))


def pk_step_numpy(pc_cur, tc, tau, clip_pos):
    pc = pc_cur - tau * tc
    neg = np.flatnonzero(pc < 0)
    clip_pos[: neg.size] = neg
    return pc, int(neg.size), float(np.maximum(pc, 0.0).sum())


def corrections_numpy(idx, clip_pos, pc, tau, ov, u, w, gbar):
    dg = u.take(ov) - w.take(ov) - gbar  # < 0: the joining cells' overlap
    pov = -tau * dg
    cells = np.concatenate([idx.take(clip_pos), ov])
    vals = np.concatenate([pc.take(clip_pos) / tau, dg])
    return cells, vals, pov, float(pov.sum())


def merge_set_numpy(idx, tc, pc, wc, ov, pov, w, scale, w_out, rin):
    keep = pc >= 0
    out = idx[~keep]
    w_out[out] = w.take(out)
    rin[out] = 0.0
    w_out[ov] = -np.inf
    idx, tc, pc, wc = idx[keep], tc[keep], pc[keep] * scale, wc[keep]
    if ov.size:
        idx = np.concatenate([idx, ov])
        order = np.argsort(idx, kind="stable")
        idx = idx[order]
        tc = np.concatenate([tc, np.zeros(ov.size)])[order]
        pc = np.concatenate([pc, pov * scale])[order]
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


def scatter_numpy(x, idx, values) -> None:
    x[idx] = values


#: the 8 neighbours of a front cell, the 4 directions of each undirected pair first
_NEIGHBOURS = ((1, 0), (0, 1), (1, 1), (1, -1), (-1, 0), (0, -1), (-1, -1), (-1, 1))


def walk_csr(rows: np.ndarray, cols: np.ndarray, n: int):
    """The lazy walk ½(I + D⁻¹ Adj) on n nodes joined by the undirected pairs (rows, cols)
    (each pair once), as a CSR matrix with sorted columns (the row order of
    :func:`front_walk`).  Row-stochastic: each step is a mean, so staircase corners of
    higher degree gain no weight (an unnormalised walk biased a JKR disc's balance by 5 %
    near pull-off); an isolated node keeps its value."""
    from scipy import sparse

    adj = sparse.coo_matrix((np.ones(rows.size), (rows, cols)), shape=(n, n)).tocsr()
    adj = (adj + adj.T).tocsr()
    deg = np.asarray(adj.sum(axis=1)).ravel()
    step = (sparse.diags(0.5 / np.maximum(deg, 1.0)) @ adj
            + sparse.diags(np.where(deg > 0, 0.5, 1.0))).tocsr()
    step.sort_indices()
    return step


def front_graph_numpy(idx, shape, nx, ny, sig):
    """(indptr, indices, data) of :func:`walk_csr` on the front cells ``idx`` (sorted flat
    cells of a periodic grid of ``shape``) joined to their 8-neighbours among them whose
    normals (nx, ny) agree (n_i·n_j > 0) and whose σ (``sig``) is the same."""
    n = idx.size
    pos = np.full(shape[0] * shape[1], -1, np.int32 if idx.size < 2**31 else np.int64)
    pos[idx] = np.arange(n)
    i, j = np.divmod(idx, shape[1])
    rows, cols = [], []
    for di, dj in _NEIGHBOURS[:4]:  # each undirected pair once
        k = pos[((i + di) % shape[0]) * shape[1] + (j + dj) % shape[1]]
        sel = k >= 0
        ks = k[sel]
        sel[sel] = (nx[sel] * nx[ks] + ny[sel] * ny[ks] > 0) & (sig[sel] == sig[ks])
        rows.append(np.flatnonzero(sel))
        cols.append(k[sel])
    step = walk_csr(np.concatenate(rows), np.concatenate(cols), n)
    return step.indptr, step.indices, step.data


def front_walk_numpy(indptr, indices, data, steps, num, den) -> None:
    """Row i of the CSR matrix (indptr, indices, data) applied steps[i] times to ``num``
    and ``den`` (in place); rows of different step counts must not be joined."""
    from scipy import sparse

    n = num.size
    step = sparse.csr_matrix((data, indices, indptr), shape=(n, n))
    for t in range(int(steps.max(initial=0))):
        act = steps > t
        num[act] = (step @ num)[act]
        den[act] = (step @ den)[act]


if numba is not None:
    from .compile_guard import install as _guard_compilation

    _guard_compilation()  # a Ctrl-C waits for a kernel's compilation to end (compile_guard)
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
    def _direction(gc, tc, beta, shift, rin, idx):  # pragma: no cover - compiled
        d = 0.0
        for k in range(idx.size):
            t = gc[k] + beta * (tc[k] - shift)
            tc[k] = t
            rin[idx[k]] = t
            d += gc[k] * t
        return d

    #: cells per block of the overlap scan: a vectorised count per block, the cells listed
    #: only in the rare blocks that have an overlap
    _SCAN_BLOCK = 256

    @_jit
    def _gap_state(u, idx, wc, pc, tc, load, gc, w_out, ov_buf):  # pragma: no cover
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
        ts = 0.0
        for k in range(n):
            g = gc[k] - gbar
            gc[k] = g
            e += pc[k] * abs(g)
            ps += pc[k]
            G += g * g
            d += g * tc[k]
            ts += tc[k]
        t_mean = ts / n if (load and n > 0) else 0.0
        # the overlap scan, block by block: a vectorised count, the cells listed only in the
        # rare blocks that have one
        m = 0
        ov_min = 0.0
        N = u.size
        B = _SCAN_BLOCK
        nb = N // B
        for b in range(nb + 1):  # nb whole blocks, then the remainder
            s = b * B
            stop = min(s + B, N)
            if b < nb:
                c = 0
                for i in range(s, s + B):  # fixed length: vectorised
                    c += (u[i] - w_out[i]) < gbar
                if c == 0:
                    continue
            for i in range(s, stop):
                x = u[i] - w_out[i]
                if x < gbar:
                    ov_buf[m] = i
                    m += 1
                    ov_min = min(ov_min, x - gbar)
        return gbar, e, ps, G, d, t_mean, m, ov_min

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
    def _corrections(idx, clip_pos, pc, tau, ov, u, w, gbar):  # pragma: no cover - compiled
        nc = clip_pos.size
        cells = np.empty(nc + ov.size, dtype=idx.dtype)
        vals = np.empty(nc + ov.size)
        pov = np.empty(ov.size)
        for j in range(nc):
            k = clip_pos[j]
            cells[j] = idx[k]
            vals[j] = pc[k] / tau
        s = 0.0
        for j in range(ov.size):
            c = ov[j]
            dg = u[c] - w[c] - gbar
            cells[nc + j] = c
            vals[nc + j] = dg
            pov[j] = -tau * dg
            s += pov[j]
        return cells, vals, pov, s

    @_jit
    def _merge_set(idx, tc, pc, wc, ov, pov, w, scale, w_out,
                   rin):  # pragma: no cover - compiled
        nov = ov.size
        m = nov
        for k in range(idx.size):
            m += pc[k] >= 0.0
        idx2 = np.empty(m, dtype=idx.dtype)
        tc2 = np.empty(m)
        pc2 = np.empty(m)
        wc2 = np.empty(m)
        o = 0
        j = 0
        for i in range(idx.size):
            c = idx[i]
            while j < nov and ov[j] < c:  # the joining cells before c
                d = ov[j]
                idx2[o] = d
                tc2[o] = 0.0
                pc2[o] = pov[j] * scale
                wc2[o] = w[d]  # only the joining cells read the full grid
                w_out[d] = -np.inf
                j += 1
                o += 1
            if pc[i] >= 0.0:
                idx2[o] = c
                tc2[o] = tc[i]
                pc2[o] = pc[i] * scale
                wc2[o] = wc[i]
                o += 1
            else:  # c leaves the contact set
                w_out[c] = wc[i]
                rin[c] = 0.0
        while j < nov:  # the joining cells after the last one (the same lines as above:
            # a shared helper made the merge 1.5× slower at 40 % dropped cells, measured)
            d = ov[j]
            idx2[o] = d
            tc2[o] = 0.0
            pc2[o] = pov[j] * scale
            wc2[o] = w[d]
            w_out[d] = -np.inf
            j += 1
            o += 1
        return idx2, tc2, pc2, wc2

    def pk_step(pc_cur, tc, tau, clip_pos):
        """(pc = pc_cur − τ·tc as a new array, the number n of its negative cells,
        Σ max(pc, 0)); their positions in pc, increasing, go to ``clip_pos[:n]``."""
        pc, nneg, total = _pk_step(pc_cur, tc, float(tau), clip_pos)
        return pc, int(nneg), float(total)

    def corrections(idx, clip_pos, pc, tau, ov, u, w, gbar):
        """The projection correction c of a PK step: the cells ``idx[clip_pos]`` that clip
        (``pc < 0``, c = −pc) and the joining cells ``ov`` (overlap u − w − ḡ < 0, c = pov).
        Returns (cells, vals, pov, Σ pov): the cells and values of −c/τ (pc/τ on clipped
        cells, u − w − ḡ on joining ones), for the direct sum D = T + FFT(−c/τ), and the
        joining cells' pressure pov = −τ(u − w − ḡ)."""
        return _corrections(idx, clip_pos, pc, float(tau), ov, u, w, float(gbar))

    def merge_set(idx, tc, pc, wc, ov, pov, w, scale, w_out, rin):
        """The contact set after a step: the cells of ``idx`` with ``pc < 0`` dropped (w_out
        and rin restored there: w and 0), the cells ``ov`` (sorted, disjoint from ``idx``)
        merged in with t = 0 and p = ``pov`` (w_out = −∞ there), every pressure times
        ``scale``; returns (idx, tc, pc, w[idx]), ``idx`` sorted (``wc`` = w[idx] on entry:
        only the joining cells are read from the full grid)."""
        return _merge_set(idx, tc, pc, wc, ov, pov, w, float(scale), w_out, rin)

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

    @_jit
    def _front_walk(indptr, indices, data, order, steps, num, den, buf):  # pragma: no cover
        n_act = order.size
        t = 0
        while n_act > 0:
            while n_act > 0 and steps[order[n_act - 1]] <= t:
                n_act -= 1
            for a in range(n_act):
                i = order[a]
                s = 0.0
                d = 0.0
                for k in range(indptr[i], indptr[i + 1]):
                    s += data[k] * num[indices[k]]
                    d += data[k] * den[indices[k]]
                buf[2 * a] = s
                buf[2 * a + 1] = d
            for a in range(n_act):
                i = order[a]
                num[i] = buf[2 * a]
                den[i] = buf[2 * a + 1]
            t += 1

    _DI = np.array([d[0] for d in _NEIGHBOURS], dtype=np.int64)
    _DJ = np.array([d[1] for d in _NEIGHBOURS], dtype=np.int64)

    @_jit
    def _front_graph(idx, nx_grid, ny_grid, nx, ny, sig, di, dj):  # pragma: no cover
        n = idx.size
        pos = np.full(nx_grid * ny_grid, -1, np.int32)  # (grids below 2³¹ cells)
        for a in range(n):
            pos[idx[a]] = a
        nb = np.full((n, 8), -1, np.int64)
        deg = np.zeros(n)
        for a in range(n):
            i = idx[a] // ny_grid
            j = idx[a] - i * ny_grid
            for d in range(8):
                k = pos[((i + di[d]) % nx_grid) * ny_grid + (j + dj[d]) % ny_grid]
                if k >= 0 and nx[a] * nx[k] + ny[a] * ny[k] > 0 and sig[a] == sig[k]:
                    nb[a, d] = k
                    deg[a] += 1.0
        # each row: the diagonal and its distinct neighbours (a neighbour met twice, on a
        # grid of one or two cells across, weighs twice, as scipy sums duplicates)
        cols = np.empty((n, 9), np.int64)
        vals = np.empty((n, 9))
        cnt = np.empty(n, np.int64)
        for a in range(n):
            cols[a, 0] = a
            vals[a, 0] = 0.0
            m = 1
            for d in range(8):
                k = nb[a, d]
                if k < 0:
                    continue
                t = 0
                while t < m and cols[a, t] != k:
                    t += 1
                if t == m:
                    cols[a, m] = k
                    vals[a, m] = 1.0
                    m += 1
                else:
                    vals[a, t] += 1.0
            for t in range(1, m):  # sorted columns (insertion sort of ≤ 9 entries)
                c, v, u = cols[a, t], vals[a, t], t - 1
                while u >= 0 and cols[a, u] > c:
                    cols[a, u + 1] = cols[a, u]
                    vals[a, u + 1] = vals[a, u]
                    u -= 1
                cols[a, u + 1] = c
                vals[a, u + 1] = v
            cnt[a] = m
        indptr = np.zeros(n + 1, np.int64)
        for a in range(n):
            indptr[a + 1] = indptr[a] + cnt[a]
        indices = np.empty(indptr[n], np.int32)
        data = np.empty(indptr[n])
        for a in range(n):
            s = 0.5 / max(deg[a], 1.0)
            diag = 0.5 if deg[a] > 0 else 1.0
            p = indptr[a]
            for t in range(cnt[a]):
                c = cols[a, t]
                indices[p + t] = c
                if c != a:
                    data[p + t] = s * vals[a, t]
                elif vals[a, t] > 0:  # a self-loop (a grid one cell across)
                    data[p + t] = s * vals[a, t] + diag
                else:
                    data[p + t] = diag
        return indptr, indices, data

    def front_graph(idx, shape, nx, ny, sig):
        """(indptr, indices, data) of the lazy walk ½(I + D⁻¹ Adj) on the front cells
        ``idx`` (sorted flat cells of a periodic grid of ``shape``) joined to their
        8-neighbours among them whose normals (nx, ny) agree (n_i·n_j > 0) and whose σ
        (``sig``) is the same: the CSR matrix of :func:`walk_csr` (sorted columns,
        duplicates summed) to the last bit, built in one compiled pass."""
        if shape[0] * shape[1] >= 2**31:
            return front_graph_numpy(idx, shape, nx, ny, sig)
        return _front_graph(np.ascontiguousarray(idx, dtype=np.int64), int(shape[0]),
                            int(shape[1]), np.ascontiguousarray(nx, dtype=float),
                            np.ascontiguousarray(ny, dtype=float),
                            np.ascontiguousarray(sig, dtype=float), _DI, _DJ)

    def front_walk(indptr, indices, data, steps, num, den) -> None:
        """Row i of the CSR matrix (indptr, indices, data) applied ``steps[i]`` times to
        ``num`` and ``den`` (float64, updated in place), rows in the CSR's column order so
        that each step is scipy's product to the last bit; rows of different step counts
        must not be joined (each connected part of the graph walks its own count)."""
        steps = np.ascontiguousarray(steps, dtype=np.int64)
        order = np.argsort(-steps, kind="stable").astype(np.int64)
        order = order[steps[order] > 0]
        _front_walk(indptr, indices, data, order, steps, num, den,
                    np.empty(2 * order.size))

    def periodic_cubic(coefs, x, y, lam, inv_dx, guard, out, near_index):
        """The periodic piecewise cubic with rows ``coefs`` (c0..c3 per cell of width
        1/inv_dx, period λ) at the distances x_j − y_i, written to ``out`` (len(x) × len(y));
        the flat indices of the distances within ``guard`` cells of 0 (mod λ) go to
        ``near_index``, their number is returned."""
        return int(_periodic_cubic(coefs, np.ascontiguousarray(x, dtype=float),
                                   np.ascontiguousarray(y, dtype=float), float(lam),
                                   float(inv_dx), float(guard), out, near_index))

    def direction(gc, tc, beta, shift, rin, idx):
        """tc ← gc + β·(tc − shift), in place, also written to ``rin[idx]``; returns
        ⟨gc, tc⟩ (shift = mean of tc under load control: the new direction is then as
        mean-free as gc)."""
        return float(_direction(gc, tc, float(beta), float(shift), rin, idx))

    def gap_state(u, idx, wc, pc, tc, load, gc, w_out, ov_buf):
        """The state after an inverse transform.  On the contact set ``idx``: gc = u[idx] −
        wc − ḡ (ḡ its mean under load control, else 0), written in place.  On the other
        cells (``w_out`` = w there, −∞ on the contact set): the overlap scan u − w_out < ḡ,
        the cells listed in ``ov_buf[:n]`` in increasing order.  Returns (ḡ, Σ pc|gc|,
        Σ pc, Σ gc², Σ gc·tc — for the descent test of the next direction —, mean tc under
        load control (else 0), n, the deepest overlap min(u − w_out) − ḡ over the n cells
        (0 when n = 0))."""
        r = _gap_state(u, idx, wc, pc, tc, bool(load), gc, w_out, ov_buf)
        return (r[0], r[1], r[2], r[3], r[4], r[5], int(r[6]), r[7])

    def parseval_sum(T: np.ndarray, k: np.ndarray, m: np.ndarray) -> float:
        """Σ m_j k_ij |T_ij|² for a complex half spectrum T, real k of the same shape and the
        column multiplicities m (length T.shape[1])."""
        return float(_parseval_sum(T, k, m))

    @_jit
    def _scatter(x, idx, values):  # pragma: no cover - compiled
        for i in range(idx.size):
            x[idx[i]] = values[i]

    def scatter(x, idx, values) -> None:
        """``x[idx] = values`` on a flat float64 field, in place (the masked solves' write of
        packed values into the FFT input: ndarray.put takes 4.4 times as long at 512²)."""
        _scatter(x, idx, values)

    def spectrum_step(P, D, a, k, s, out) -> None:
        """P ← P + a·D (in place) and out = s·k·P, in one pass (contiguous arrays)."""
        if not (P.flags.c_contiguous and out.flags.c_contiguous):
            raise ValueError("spectrum_step needs C-contiguous P and out (updated in place)")
        _spectrum_step(P.reshape(-1), D.reshape(-1), float(a), k.reshape(-1), float(s),
                       out.reshape(-1))

else:  # pragma: no cover - the numpy build
    parseval_sum = parseval_sum_numpy
    spectrum_step = spectrum_step_numpy
    direction = direction_numpy
    gap_state = gap_state_numpy
    pk_step = pk_step_numpy
    merge_set = merge_set_numpy
    corrections = corrections_numpy
    periodic_cubic = periodic_cubic_numpy
    front_walk = front_walk_numpy
    front_graph = front_graph_numpy
    scatter = scatter_numpy
