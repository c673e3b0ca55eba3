"""The compute-backend seam: every grid computation of an operator runs through its backend
(FFT plans, kernel product, fused loops, masked gather/scatter); the numpy backend gives the
compiled one's answers; a backend registered in one place is used end to end; a kernel may
be a block per mode."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from spectralbem import backend, fft
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


_THREADS_PROBE = """
import json
import numpy as np
from spectralbem import fft
from threadpoolctl import ThreadpoolController

def os_threads():
    with open("/proc/self/status") as f:
        return int(next(line.split()[1] for line in f if line.startswith("Threads:")))

def omp():
    return {c.filepath: c.num_threads for c in ThreadpoolController().lib_controllers}

x = np.random.default_rng(0).random((512, 512))
out = dict(before=os_threads(), libs=omp())
one = fft.plan((512, 512), 1).forward(x).copy()
out["after_one"] = os_threads()
two = fft.plan((512, 512), 2).forward(x).copy()
out.update(after_two=os_threads(), libs_now=omp(),
           diff=float(np.abs(two - one).max() / np.abs(one).max()))
print(json.dumps(out))
"""


@pytest.mark.skipif(fft.backend() != "pyfftw" or not sys.platform.startswith("linux"),
                    reason="pyFFTW's OpenMP build, threads counted in /proc")
def test_an_fft_plan_of_two_threads_runs_two_where_openmp_is_capped_at_one():
    """With OMP_NUM_THREADS=1 (as a dask worker or a bench sets it) a 2-thread FFTW plan
    used to run on one thread: FFTW's OpenMP loops take the runtime's team size.  Now the
    plan raises pyFFTW's OpenMP runtime (only it) to 2 and the transform starts a second OS
    thread; a 1-thread plan starts none; the answers agree to round-off."""
    # FFTW_ESTIMATE: the plan (threaded or not) chosen without timing, the same everywhere
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1",
               SPECTRALBEM_FFTW_PLANNER="estimate")
    run = subprocess.run([sys.executable, "-c", _THREADS_PROBE], env=env, check=True,
                         capture_output=True, text=True)
    r = json.loads(run.stdout)
    assert r["after_one"] == r["before"]
    assert r["after_two"] > r["after_one"]
    assert r["diff"] < 1e-13
    assert any("pyfftw" in path for path in r["libs"])
    for path, n in r["libs_now"].items():
        if "pyfftw" in path:
            assert (r["libs"][path], n) == (1, 2)
        else:  # BLAS and any other runtime keep the environment's limit
            assert n == r["libs"][path]


def test_a_threaded_solve_holds_blas_to_one_thread_and_gives_the_same_state():
    """Two FFTW threads and a multi-threaded BLAS fight for the cores (the Krylov solves'
    small BLAS products between transforms: 4× slower at 512², docs/performance.md), so a
    solve whose operator has more than one FFT thread runs BLAS on one; one FFT thread leaves
    BLAS as it was.  The threaded solve reaches the single-threaded state: the same contact
    set, pressures within 1e-9 of the peak (both solved to the default 1e-10; only the
    transforms' rounding differs)."""
    from threadpoolctl import threadpool_info

    seen = []

    def blas_threads():
        return [lib["num_threads"] for lib in threadpool_info() if lib["user_api"] == "blas"]

    before = blas_threads()
    with fft.fft_threads_only(2):
        seen.append(blas_threads())
    with fft.fft_threads_only(1):
        seen.append(blas_threads())
    assert blas_threads() == before
    assert all(n == 1 for n in seen[0])
    assert seen[1] == before
    cell = Cell(1.0, 1.0, 32, 32)
    h = paraboloid(cell, 2.0)
    states = [solve_adhesive(SpectralOperator(cell, SLS, velocity=(0.1, 0.0), threads=t),
                             h, 0.002, 2 * cell.hx, mean_pressure=0.003) for t in (1, 2)]
    assert states[0].status == states[1].status == "partial", states[0].message
    np.testing.assert_array_equal(states[0].contact, states[1].contact)
    np.testing.assert_allclose(states[1].pressure, states[0].pressure, rtol=0,
                               atol=1e-9 * np.abs(states[0].pressure).max())


def _counting(monkeypatch):
    """Wrap the plans' transform methods with counters of their own (the plans' counters
    are incremented inside the wrapped methods): {'forward': n, 'inverse': n}."""
    seen = {"forward": 0, "inverse": 0}
    for name, kind in (("forward", "forward"), ("forward_buffer", "forward"),
                       ("inverse_buffer", "inverse")):
        orig = getattr(fft.RealFFT2, name)

        def wrapped(self, *a, _orig=orig, _kind=kind, **k):
            seen[_kind] += 1
            return _orig(self, *a, **k)
        monkeypatch.setattr(fft.RealFFT2, name, wrapped)
    return seen


def test_transform_counts_count_every_transform_of_every_plan():
    """A plan counts each forward (from a field or its input buffer) and each inverse
    (``inverse`` runs ``inverse_buffer`` once), and transform_counts sums every plan."""
    before = fft.transform_counts()
    a, b = fft.plan((12, 10)), fft.plan((8, 6), use_fftw=False)
    x = np.random.default_rng(0).random((12, 10))
    X = a.forward(x).copy()
    a.input_buffer[...] = x
    a.forward_buffer()
    a.inverse(X)
    b.inverse(b.forward(np.ones((8, 6))).copy())
    assert np.subtract(fft.transform_counts(), before).tolist() == [3, 2]


def test_a_solve_reports_its_transforms(monkeypatch):
    """The dataset's solver_diagnostics carry the solve's FFTs (``fft_transforms``): those
    that wrappers of the plans' methods count, for an adhesive path of two steps (each
    step its own count) and an adhesiveless solve; one operator application is one pair."""
    from pathlib import Path

    from spectralbem.scenes import load_scene, solve

    case = Path(__file__).resolve().parent.parent / "cases" / "jkr_sphere.toml"
    seen = _counting(monkeypatch)
    grid = {"grid.Nx": 64, "grid.Ny": 64, "adhesion.a0": 1e-3 / 64}
    ds = solve(load_scene(case, overrides={**grid, "control.mean_pressure": [1e3, 5e2]}))
    steps = json.loads(ds.attrs["solver_diagnostics"])
    counts = [s["fft_transforms"] for s in steps]
    assert all(c["inverse"] > 0 for c in counts)
    assert {k: sum(c[k] for c in counts) for k in seen} == seen
    seen.update(forward=0, inverse=0)
    ds = solve(load_scene(case, overrides={**grid, "adhesion.dgamma": 0.0,
                                           "control.mean_pressure": 1e3}))
    assert json.loads(ds.attrs["solver_diagnostics"])["fft_transforms"] == seen
    assert seen["inverse"] > 0


def test_transform_counts_leave_out_other_threads():
    """Another thread's transforms (its own plans) are not in this thread's count."""
    import threading

    before = fft.transform_counts()
    t = threading.Thread(target=lambda: fft.plan((12, 10)).forward(np.ones((12, 10))))
    t.start()
    t.join()
    fft.plan((12, 10)).forward(np.ones((12, 10)))
    assert np.subtract(fft.transform_counts(), before).tolist() == [1, 0]
