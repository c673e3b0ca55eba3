"""spectralbem: spectral BEM contact of rigid rough surfaces on (visco)elastic slabs."""

__version__ = "0.1.0"

from .scenes import Scene, solve  # noqa: E402,F401
