"""The seed's 1D method under its historical name: everything lives in :mod:`spectralbem.oned`
(``spectralbem.sinusoid1d.solve`` is ``spectralbem.oned.solve``)."""

from .oned import *  # noqa: F403
from .oned import __all__  # noqa: F401
