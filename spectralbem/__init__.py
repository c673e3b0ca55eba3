"""spectralbem: spectral BEM contact of rigid rough surfaces on (visco)elastic slabs.

``spectralbem.Scene`` and ``spectralbem.solve`` are imported on first use, so that
``import spectralbem`` and the command line's ``--help`` do not load the numerical stack
(numpy, the FFT libraries, numba, dask).
"""

__version__ = "0.1.0"

__all__ = ["Scene", "solve", "__version__"]


def __getattr__(name: str):
    if name in ("Scene", "solve"):
        from . import scenes

        return getattr(scenes, name)
    raise AttributeError(f"module 'spectralbem' has no attribute {name!r}")


def __dir__():
    return sorted(list(globals()) + ["Scene", "solve"])
