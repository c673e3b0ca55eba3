import signal

import matplotlib
import numpy as np
import pytest

matplotlib.use("Agg")


def pytest_configure(config):
    """The Ctrl-C tests send SIGINT as a terminal does.  A run started with SIGINT ignored
    (a background job of a non-interactive shell: `( make test & )`) passes that on to
    every process the tests start, and a process that inherits an ignored SIGINT rightly
    keeps ignoring it; Python's own handler here gives the tests' processes the default
    disposition a terminal's have."""
    if signal.getsignal(signal.SIGINT) is signal.SIG_IGN:
        signal.signal(signal.SIGINT, signal.default_int_handler)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)


@pytest.fixture
def canned_validate(monkeypatch):
    """spectralbem.validate with its comparisons replaced by canned rows (2D = 1D exactly):
    the report and its figure are written without the minutes of the real solves."""
    from spectralbem import validate as v

    def fake(zeta, p_tilde, direction_deg=0.0, ny=2, n=None):
        row = {"zeta": zeta, "p_tilde": p_tilde, "N": n or 1024, "a0_eff": v.A0,
               "time_2d": 0.0, "status": "partial"}
        row.update({k: (1.0, 1.0, 0.0) for k in v.KEYS})
        if direction_deg:
            row["mu_lateral"] = (0.0, 0.0)
        return row

    monkeypatch.setattr(v, "compare", fake)
    return v
