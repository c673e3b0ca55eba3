"""The compute-backend seam: every grid computation of an operator runs through its backend
(FFT plans, kernel product, fused loops, masked gather/scatter); the numpy backend gives the
compiled one's answers; a backend registered in one place is used end to end; a kernel may
be a block per mode."""

import numpy as np
import pytest

from spectralbem import backend
from spectralbem.adhesive import solve_adhesive
from spectralbem.contact import solve_contact
from spectralbem.materials import Elastic, StandardLinearSolid
from spectralbem.spectral import Cell, SpectralOperator
from spectralbem.surfaces import paraboloid, self_affine

CELL = Cell(1.0, 1.0, 48, 40)
H = self_affine(CELL, 0.8, rolloff=2 * np.pi * 4, cutoff=2 * np.pi / (4 * CELL.hx),
                rms_slope=0.1, seed=7)
SLS = StandardLinearSolid(1.0, 10.0, 1.0, 0.5)


def test_numpy_backend_gives_the_compiled_answers():
    """Viscoelastic adhesiveless contact (Newton, masked GMRES) under both backends: the same
    contact set, pressures within 1e-8 (both solved to 1e-10; the backends differ by the
    summation order of the transforms and loops only)."""
    out = {}
    for name in ("cpu", "numpy"):
        op = SpectralOperator(CELL, SLS, velocity=(0.1, 0.0), backend=name)
        assert op.backend.name == name
        out[name] = solve_contact(op, H, mean_pressure=0.01, tol=1e-10)
        assert out[name].converged, out[name].message
    a, b = out["cpu"], out["numpy"]
    np.testing.assert_array_equal(a.contact, b.contact)
    assert np.linalg.norm(a.pressure - b.pressure) <= 1e-8 * np.linalg.norm(a.pressure)


class Counting(backend.Backend):
    """A backend that counts what passes through the seam (numpy underneath)."""

    def __init__(self):
        base = backend.get("numpy")
        super().__init__("counting", base.plan, base.loops, "numpy", "numpy")
        self.products = self.gathers = 0

    def apply_kernel(self, plan, p, k):
        self.products += 1
        return super().apply_kernel(plan, p, k)

    def gather(self, x, idx):
        self.gathers += 1
        return x.take(idx)


def test_a_registered_backend_runs_the_adhesive_solve():
    """An adhesive JKR-like state on a sphere with a backend registered here: the same state
    as the default backend's, and the work went through the seam."""
    made = Counting()
    backend.register("counting", lambda: made)
    try:
        cell = Cell(1.0, 1.0, 32, 32)
        h = paraboloid(cell, 2.0)
        res = {}
        for name in ("cpu", "counting"):
            op = SpectralOperator(cell, Elastic(1.0, 0.5), backend=name)
            res[name] = solve_adhesive(op, h, 0.002, 2 * cell.hx, mean_pressure=0.001)
            assert res[name].status == "partial", res[name].message
        np.testing.assert_array_equal(res["cpu"].contact, res["counting"].contact)
        assert made.products > 0 and made.gathers > 0
        assert "counting" in backend.names()
    finally:
        backend._FACTORIES.pop("counting", None)
        backend._MADE.pop("counting", None)


def test_block_kernel_per_mode():
    """A 2 × 2 block per mode: a diagonal block applies each scalar kernel to its component;
    a coupling block gives u_i = Σ_j C_ij p_j, checked against the scalar applications."""
    op = SpectralOperator(CELL, Elastic(1.0, 0.3))
    other = SpectralOperator(CELL, Elastic(2.5, 0.3))
    k1, k2 = op._k, other._k
    rng = np.random.default_rng(0)
    p = rng.standard_normal((2,) + CELL.shape)
    zero = np.zeros_like(k1)
    diag = np.stack([np.stack([k1, zero]), np.stack([zero, k2])])
    u = op.backend.apply_kernel(op.plan, p, diag)
    np.testing.assert_allclose(u[0], op.apply(p[0]), rtol=0, atol=1e-13)
    np.testing.assert_allclose(u[1], other.apply(p[1]), rtol=0, atol=1e-13)
    coupled = np.stack([np.stack([k1, 0.5 * k2]), np.stack([0.5 * k2, k1])])
    u = op.backend.apply_kernel(op.plan, p, coupled)
    np.testing.assert_allclose(u[0], op.apply(p[0]) + 0.5 * other.apply(p[1]), rtol=0,
                               atol=1e-13)
    with pytest.raises(ValueError, match="2 components"):
        op.backend.apply_kernel(op.plan, p[:1], coupled)


def test_unknown_backend_is_refused():
    with pytest.raises(ValueError, match="backend = 'gpu'; allowed: cpu, numpy"):
        SpectralOperator(CELL, Elastic(1.0, 0.3), backend="gpu")
