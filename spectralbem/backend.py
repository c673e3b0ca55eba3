"""Compute backends: where a spectral operator's arithmetic runs.

A :class:`Backend` holds everything the solvers do on the grid outside plain numpy
bookkeeping: the planned real FFT pairs with their buffers (:meth:`Backend.plan`), the
product by the kernel between two transforms (:meth:`Backend.apply_kernel`, a scalar per
mode or a small b × b block per mode), the fused loops of the Polonsky–Keer iteration
(:attr:`Backend.loops`, the functions of :mod:`spectralbem.kernels`) and the gather/scatter
of the masked solves (:meth:`Backend.gather`, :meth:`Backend.scatter`).  Each
:class:`~spectralbem.spectral.SpectralOperator` carries one (``backend=`` name or object).

Built in:

* ``"cpu"`` (the default) — planned pyFFTW transforms and the numba-compiled loops, each
  falling back to numpy when its library is missing or switched off (``SPECTRALBEM_FFT=numpy``,
  ``SPECTRALBEM_JIT=0``);
* ``"numpy"`` — numpy's FFT and the numpy twins of the loops: the reference the compiled
  backend is tested against.

Another backend (a GPU array library, say) is one new module that builds a :class:`Backend`
whose plan, loops and kernel product run there, and calls :func:`register`; the default is
chosen by ``SPECTRALBEM_BACKEND``.
"""

from __future__ import annotations

import os
from types import SimpleNamespace
from typing import Callable

import numpy as np

__all__ = ["Backend", "get", "register", "names", "LOOPS"]

#: the fused loops every backend provides (:mod:`spectralbem.kernels`)
LOOPS = ("parseval_sum", "spectrum_step", "direction", "gap_state", "pk_step", "corrections",
         "merge_set", "scatter")


class Backend:
    """FFT plans, kernel product, fused loops and gather/scatter of one compute target.

    ``plan_factory(shape, threads)`` returns a transform pair with the interface of
    :class:`spectralbem.fft.RealFFT2`; ``loops`` has the functions named in :data:`LOOPS`.
    """

    def __init__(self, name: str, plan_factory: Callable, loops, fft_name: str,
                 loops_name: str):
        missing = [f for f in LOOPS if not hasattr(loops, f)]
        if missing:
            raise ValueError(f"backend {name!r}: loops lack {', '.join(missing)}")
        self.name = name
        self._plan_factory = plan_factory
        self.loops = loops
        self.fft_name = fft_name
        self.loops_name = loops_name

    def __repr__(self) -> str:
        return f"Backend({self.name!r}: FFT {self.fft_name}, loops {self.loops_name})"

    def plan(self, shape, threads: int | None = None):
        """The transform pair of ``shape`` (cached by the factory)."""
        return self._plan_factory(shape, threads)

    def apply_kernel(self, plan, p: np.ndarray, k: np.ndarray) -> np.ndarray:
        """F⁻¹[k] F p with the unnormalised inverse of ``plan`` (k carries the 1/(Nx Ny)).

        ``k`` of the half-spectrum's shape: one multiplier per mode, ``p`` a field; ``k`` of
        shape (b, b, Nx, Ny//2+1): a block per mode (e.g. a tangential coupling), ``p`` of
        shape (b, Nx, Ny) and the result too, ``u_i = F⁻¹[Σ_j k_ij F p_j]``.  The returned
        array of a scalar kernel is the plan's buffer (the next inverse overwrites it)."""
        if k.ndim == 2:
            np.multiply(plan.forward(p), k, out=plan.spectrum_buffer)
            return plan.inverse_buffer()
        b = k.shape[0]
        if k.shape[:2] != (b, b) or p.shape[0] != b:
            raise ValueError(f"a block kernel {k.shape[:2]} needs fields of {b} components; "
                             f"got {p.shape[0]}")
        P = np.stack([plan.forward(p[j]).copy() for j in range(b)])
        out = np.empty(p.shape)
        for i in range(b):
            np.einsum("jxy,jxy->xy", k[i], P, out=plan.spectrum_buffer)
            out[i] = plan.inverse_buffer()
        return out

    @staticmethod
    def gather(x: np.ndarray, idx: np.ndarray) -> np.ndarray:
        """The values of the flat field ``x`` on the cells ``idx`` (packed, a new array)."""
        return x.take(idx)

    def scatter(self, x: np.ndarray, idx: np.ndarray, values: np.ndarray) -> None:
        """``x[idx] = values`` on the flat float64 field ``x``, in place (the loops')."""
        self.loops.scatter(x, idx, values)


def _numpy_loops():
    from . import kernels

    return SimpleNamespace(**{f: getattr(kernels, f"{f}_numpy") for f in LOOPS})


def _cpu() -> Backend:
    from . import fft, kernels

    return Backend("cpu", lambda shape, threads: fft.plan(shape, threads), kernels,
                   fft.backend(), kernels.backend())


def _numpy() -> Backend:
    from . import fft

    return Backend("numpy", lambda shape, threads: fft.plan(shape, threads, use_fftw=False),
                   _numpy_loops(), "numpy", "numpy")


_FACTORIES: dict = {"cpu": _cpu, "numpy": _numpy}
_MADE: dict = {}


def register(name: str, factory: Callable[[], Backend]) -> None:
    """Make ``factory()`` available as the backend ``name`` (built on first use)."""
    _FACTORIES[name] = factory
    _MADE.pop(name, None)


def names() -> list:
    return list(_FACTORIES)


def get(backend=None) -> Backend:
    """The backend named ``backend`` (a :class:`Backend` is returned as is; None: the one
    ``SPECTRALBEM_BACKEND`` names, default ``"cpu"``)."""
    if isinstance(backend, Backend):
        return backend
    name = backend or os.environ.get("SPECTRALBEM_BACKEND", "cpu")
    if name not in _FACTORIES:
        raise ValueError(f"backend = {name!r}; allowed: {', '.join(_FACTORIES)}")
    if name not in _MADE:
        _MADE[name] = _FACTORIES[name]()
    return _MADE[name]
