"""spectralbem: spectral BEM contact of rigid rough surfaces on (visco)elastic slabs."""

__version__ = "0.1.0"

