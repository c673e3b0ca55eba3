"""Planned real 2D FFTs: pyFFTW (FFTW_MEASURE plans cached per shape and thread count) with a
numpy fallback.

The spatial kernel is real, so only real-to-complex (r2c) and complex-to-real (c2r) transforms
are used: a field of shape (Nx, Ny) maps to a half spectrum of shape (Nx, Ny//2 + 1).  The
inverse is *unnormalised* (FFTW's convention); the spectral operator folds the 1/(Nx Ny) into
its kernel, so one operator application is exactly one forward and one inverse transform.

Configuration: ``set_threads(n)`` (default 1), environment variable ``SPECTRALBEM_FFT=numpy``
to force the fallback, ``backend()`` tells which is in use.

Cost: every plan counts the transforms it runs; :func:`transform_counts` sums them over the
calling thread's plans (a solve's count is the difference around it: the machine-independent
measure of its cost that the solvers report, one operator application being one pair).

Reproducibility: a run is bit-identical to another with the same plan.  FFTW_MEASURE (the
default, fastest) picks its algorithm by timing, so two processes may, rarely, get plans that
differ in the last bit; ``SPECTRALBEM_FFTW_PLANNER=estimate`` makes the plan choice
deterministic (bit-identical results across processes and runs, slightly slower transforms).
"""

from __future__ import annotations

import contextlib
import functools
import os
import threading

import numpy as np
from scipy.linalg.blas import zgemm

try:  # pragma: no cover - exercised through backend()
    import pyfftw

    _HAVE_PYFFTW = os.environ.get("SPECTRALBEM_FFT", "").lower() != "numpy"
except ImportError:  # pragma: no cover
    pyfftw = None
    _HAVE_PYFFTW = False

_THREADS = 1
_PLANNERS = {"measure": "FFTW_MEASURE", "estimate": "FFTW_ESTIMATE", "patient": "FFTW_PATIENT"}


def planner() -> str:
    """The FFTW planner flag from ``SPECTRALBEM_FFTW_PLANNER`` (default 'measure')."""
    name = os.environ.get("SPECTRALBEM_FFTW_PLANNER", "measure").lower()
    if name not in _PLANNERS:
        raise ValueError(f"SPECTRALBEM_FFTW_PLANNER = {name!r} is not one of "
                         f"{', '.join(_PLANNERS)}")
    return _PLANNERS[name]

_PLANS: dict = {}
_LOCK = threading.Lock()


def backend() -> str:
    """'pyfftw' or 'numpy'."""
    return "pyfftw" if _HAVE_PYFFTW else "numpy"


def set_threads(n: int) -> None:
    """Number of FFT threads for plans created from now on (default 1)."""
    global _THREADS
    n = int(n)
    if n < 1:
        raise ValueError(f"threads = {n} must be >= 1")
    _THREADS = n


def get_threads() -> int:
    return _THREADS


def allow_openmp_threads(threads: int) -> None:
    """Let FFTW run plans of ``threads`` threads from the calling thread.

    pyFFTW's wheels link FFTW's OpenMP build, whose parallel loops take their team size from
    the OpenMP runtime, not from the plan: where ``OMP_NUM_THREADS=1`` (set by job schedulers,
    dask workers and this package's benches to keep BLAS on one thread) a plan of 2 threads
    runs on one.  This raises, never lowers, the calling thread's OpenMP thread count of the
    runtime pyFFTW loaded (its bundled libgomp; where it has none, every OpenMP runtime of the
    process) to ``threads``.  Called before each pyFFTW plan of more than one thread is made
    (plans are per calling thread), so that FFTW_MEASURE times the threaded algorithms.
    """
    if threads <= 1 or not _HAVE_PYFFTW:
        return
    from threadpoolctl import ThreadpoolController

    libs = [c for c in ThreadpoolController().lib_controllers if c.user_api == "openmp"]
    home = os.path.dirname(os.path.dirname(os.path.abspath(pyfftw.__file__)))
    own = [c for c in libs if os.path.abspath(c.filepath).startswith(
        os.path.join(home, "pyfftw"))]  # pyfftw/ or the wheel's pyfftw.libs/
    for c in own or libs:
        if c.num_threads < threads:
            c.set_num_threads(threads)


_BLAS = None  # threadpoolctl's controller of the process's BLAS libraries, made on first use


@contextlib.contextmanager
def fft_threads_only(threads: int | None):
    """BLAS on one thread while FFTW runs ``threads`` > 1 (a no-op otherwise).

    The solvers' BLAS calls are small products (the Gram–Schmidt passes of the Krylov
    solves, a few rows against one vector) between transforms.  With two FFTW threads and a
    multi-threaded BLAS both thread pools spin for the cores between calls: the rough SLS
    adhesive state of docs/rough_convergence.md at 512² took 91 s instead of 23 s
    (2 cores; docs/performance.md).  With one FFT thread the BLAS threads cost nothing
    measurable (25.8 against 25.6 s), so only threaded solves limit them.
    """
    threads = _THREADS if threads is None else int(threads)
    if threads <= 1 or not _HAVE_PYFFTW:
        yield
        return
    global _BLAS
    if _BLAS is None:
        from threadpoolctl import ThreadpoolController

        _BLAS = ThreadpoolController().select(user_api="blas")
    with _BLAS.limit(limits=1):
        yield


def with_fft_threads_only(solver):
    """Decorator: run ``solver(op, ...)`` under :func:`fft_threads_only` of ``op.threads``."""
    @functools.wraps(solver)
    def run(op, *args, **kwargs):
        with fft_threads_only(getattr(op, "threads", None)):
            return solver(op, *args, **kwargs)
    return run


class RealFFT2:
    """Forward r2c / unnormalised inverse c2r pair for one real shape.

    ``forward(x)`` and ``inverse(X)`` return views of internal buffers that the next call of the
    same direction overwrites: copy them if they must persist.
    """

    def __init__(self, shape, threads: int = 1, use_fftw: bool = _HAVE_PYFFTW):
        self.shape = tuple(int(n) for n in shape)
        self.hshape = (self.shape[0], self.shape[1] // 2 + 1)
        self.threads = threads
        self.use_fftw = use_fftw
        self.forward_count = self.inverse_count = 0  # transforms run (transform_counts)
        if use_fftw:
            allow_openmp_threads(threads)
            self._rin = pyfftw.zeros_aligned(self.shape, dtype="float64")
            self._cout = pyfftw.empty_aligned(self.hshape, dtype="complex128")
            self._cin = pyfftw.empty_aligned(self.hshape, dtype="complex128")
            self._rout = pyfftw.empty_aligned(self.shape, dtype="float64")
            # the r2c keeps its input (FFTW's default without DESTROY_INPUT: callers may keep
            # a sparse field in input_buffer); the c2r may destroy its spectrum
            # (a multi-dimensional c2r cannot preserve it)
            self._fwd = pyfftw.FFTW(self._rin, self._cout, axes=(0, 1), direction="FFTW_FORWARD",
                                    flags=(planner(),), threads=threads)
            self._bwd = pyfftw.FFTW(self._cin, self._rout, axes=(0, 1),
                                    direction="FFTW_BACKWARD",
                                    flags=(planner(), "FFTW_DESTROY_INPUT"), threads=threads)
        else:
            self._rin = np.zeros(self.shape)

    # -- transforms -------------------------------------------------------------------------
    def forward(self, x: np.ndarray) -> np.ndarray:
        self.forward_count += 1
        if self.use_fftw:
            self._rin[...] = x
            self._fwd.execute()
            return self._cout
        return np.fft.rfft2(x)

    @property
    def input_buffer(self) -> np.ndarray:
        """Input buffer of the forward transform (write a field, then ``forward_buffer``);
        :meth:`forward` overwrites it."""
        return self._rin

    def forward_buffer(self) -> np.ndarray:
        """r2c of :attr:`input_buffer`, which is preserved (no copy of the field)."""
        self.forward_count += 1
        if self.use_fftw:
            self._fwd.execute()
            return self._cout
        return np.fft.rfft2(self._rin)

    @property
    def spectrum_buffer(self) -> np.ndarray:
        """Input buffer of the inverse transform (write a spectrum, then ``inverse_buffer``)."""
        if self.use_fftw:
            return self._cin
        if not hasattr(self, "_cin"):
            self._cin = np.empty(self.hshape, dtype=np.complex128)
        return self._cin

    def inverse_buffer(self) -> np.ndarray:
        """Unnormalised c2r of :attr:`spectrum_buffer` (destroys it)."""
        self.inverse_count += 1
        if self.use_fftw:
            self._bwd.execute()
            return self._rout
        return np.fft.irfft2(self._cin, s=self.shape) * (self.shape[0] * self.shape[1])

    def add_sparse(self, X: np.ndarray, index: np.ndarray, values: np.ndarray) -> None:
        """``X += r2c(x)`` for a field ``x`` that is zero except ``x.flat[index] = values``,
        in place, by the direct sum over the k cells (a rank-k product, zgemm): cheaper than a
        transform when k is small (at 512², k ≲ 18 cells; docs/performance.md).  The phases
        are taken from tables at integer positions ``(m·q) mod N``, so the result equals the
        transform's to rounding (≈ 1e-16 relative per term).  ``X`` must be C-contiguous."""
        if not X.flags.c_contiguous or X.shape != self.hshape:
            raise ValueError(f"add_sparse: X must be a C-contiguous {self.hshape} spectrum")
        nx, ny = self.shape
        if not hasattr(self, "_phase"):
            self._phase = (np.exp(-2j * np.pi * np.arange(nx) / nx),
                           np.exp(-2j * np.pi * np.arange(ny) / ny))
        ex, ey = self._phase
        ix, iy = np.divmod(np.asarray(index, dtype=np.int64), ny)
        a = ey[np.multiply.outer(iy, np.arange(self.hshape[1])) % ny]  # k × (Ny/2+1)
        b = ex[np.multiply.outer(ix, np.arange(nx)) % nx]  # k × Nx
        b *= np.asarray(values, dtype=float)[:, None]
        # X (C order, Nx × Nyh) is Xᵀ in Fortran order: Xᵀ += aᵀ b
        r = zgemm(1.0, a.T, b, beta=1.0, c=X.T, overwrite_c=1)
        if not np.shares_memory(r, X):  # pragma: no cover - zgemm copied c
            X.T[...] = r

    def inverse(self, X: np.ndarray) -> np.ndarray:
        """Unnormalised c2r transform: ``inverse(forward(x)) == Nx*Ny*x``."""
        self.spectrum_buffer[...] = X
        return self.inverse_buffer()


def plan(shape, threads: int | None = None, use_fftw: bool = _HAVE_PYFFTW) -> RealFFT2:
    """The cached transform pair for ``shape`` (planned once per shape and thread count;
    ``use_fftw=False``: numpy's transforms behind the same interface).

    Plans are per thread of the caller too, because their buffers are not shareable.
    """
    threads = _THREADS if threads is None else int(threads)
    use_fftw = bool(use_fftw and _HAVE_PYFFTW)
    key = (tuple(shape), threads, use_fftw, threading.get_ident(), planner())
    with _LOCK:
        p = _PLANS.get(key)
        if p is None:
            p = RealFFT2(shape, threads, use_fftw)
            _PLANS[key] = p
    return p


def transform_counts() -> tuple[int, int]:
    """(forward, inverse): the transforms run so far by the calling thread's plans (plans are
    per thread, so a solve's count, the difference of two calls around it, leaves out other
    threads' solves, and the counters need no lock)."""
    me = threading.get_ident()
    with _LOCK:
        plans = [p for key, p in _PLANS.items() if key[3] == me]
    return (sum(p.forward_count for p in plans), sum(p.inverse_count for p in plans))
