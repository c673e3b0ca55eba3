"""Sweeps on dask.distributed: resume after a killed driver (SIGKILL to the process group),
a killed worker (dask retries), truncated point files (recomputed, never trusted)."""

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import spectralbem as sb
from spectralbem import sweep
from spectralbem.io import read_dataset
from spectralbem.scenes import load_scene
from spectralbem.schema import SceneError
from spectralbem.sweep import parse_over, resolve_key, run_sweep

CASE = Path(__file__).resolve().parent.parent / "cases" / "seed_sinusoid_1d.toml"
ZETAS = [float(z) for z in np.geomspace(0.1, 10.0, 6)]


def test_parse_over_and_keys():
    assert parse_over("zeta=1e-3:1e2:6:log")[1] == pytest.approx(np.geomspace(1e-3, 1e2, 6))
    assert parse_over("p_tilde=0.1,0.2")[1] == [0.1, 0.2]
    assert parse_over("x=0:1:3")[1] == [0.0, 0.5, 1.0]
    for bad in ("zeta", "zeta=1:2", "zeta=-1:2:3:log", "zeta=1:2:0", "zeta=a,b", "z=1:2:3:cube"):
        with pytest.raises(SceneError, match="--over"):
            parse_over(bad)
    raw = {"sinusoid": {"zeta": 1.0}}
    assert resolve_key(raw, "zeta") == "sinusoid.zeta"
    with pytest.raises(SceneError, match="not a key of this scene"):
        resolve_key(raw, "speed")


def test_swept_values_are_each_given_once_and_whole_numbers_stay_exact(tmp_path):
    """A value given twice is refused before any solve (it was solved twice, and the axis
    then indexed two points by one value); a whole number as written is kept exact (seeds
    above 2**53 were rounded through a float: 9007199254740993 solved as ...992)."""
    with pytest.raises(SceneError, match=r"sinusoid.zeta: 0.1 given more than once"):
        run_sweep(CASE, [parse_over("zeta=0.1,0.1,1")], tmp_path / "d.nc", progress=False)
    assert not (tmp_path / "d.nc.parts").exists()
    with pytest.raises(SceneError, match=r"given more than once"):
        run_sweep(CASE, [parse_over("zeta=1:1:3")], tmp_path / "d.nc", progress=False)
    big = parse_over("surface.seed=9007199254740993,12345678901234567")[1]
    assert big == [9007199254740993, 12345678901234567]
    raw = {"surface": {"kind": "self_affine"}}
    assert [sweep._typed(raw, "surface.seed", v) for v in big] == big
    assert parse_over("zeta=1,2.5")[1] == [1, 2.5]
    assert sweep._typed({"sinusoid": {}}, "sinusoid.zeta", 1) == 1.0


def test_swept_values_may_be_a_numpy_array(tmp_path):
    """``run_sweep`` takes an axis's values as a numpy array (np.geomspace, as
    bench/sweep2d.py passes them): the check for repeated values raised AttributeError
    ('numpy.ndarray' object has no attribute 'count') before any point was built."""
    with pytest.raises(SceneError, match=r"sinusoid.zeta: 0.1 given more than once"):
        run_sweep(CASE, [("zeta", np.array([0.1, 0.1, 1.0]))], tmp_path / "d.nc",
                  progress=False)
    sweep._check_axes(["sinusoid.zeta"], [("zeta", np.geomspace(1e-3, 1e2, 25))], 1)


def test_bare_swept_keys_are_looked_up_in_the_scene_as_set(tmp_path):
    """A bare ``--over`` key of a section that ``--set`` adds (a layer on a half-space
    scene) is that section's key ("not a key of this scene" before): the points are
    validated as layer.thickness (the second refused by its range, before any solve)."""
    jkr = CASE.parent / "jkr_sphere.toml"
    with pytest.raises(SceneError, match=r"point 1 .*layer.thickness"):
        run_sweep(jkr, [("thickness", [1e-4, -1.0])], tmp_path / "l.nc", progress=False,
                  overrides={"layer.kind": "glued", "layer.thickness": 1e-4})
    assert not (tmp_path / "l.nc.parts").exists()


def reference(zetas):
    """The uninterrupted result, solved point by point in this process."""
    out = []
    for z in zetas:
        ds = sb.solve(load_scene(CASE, overrides={"sinusoid.zeta": z}))
        out.append({k: ds[k].item() for k in ds.data_vars if ds[k].dims == ()})
    return out


def assert_matches(ds, ref):
    assert ds.sizes["zeta"] == len(ref)
    for i, r in enumerate(ref):
        for k, v in r.items():
            got = ds[k].values[i]
            if isinstance(v, str):
                assert got == v
            else:  # the same code on the same machine: bit-identical (nan == nan)
                np.testing.assert_array_equal(got, v, err_msg=k)


def stats(parts):
    return {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in parts.glob("point_*.nc")}


@pytest.fixture(scope="module")
def ref6():
    return reference(ZETAS)


def test_killed_sweep_resumes_without_recomputing(tmp_path, ref6):
    out = tmp_path / "z.nc"
    cmd = [sys.executable, "-m", "spectralbem.cli", "sweep", str(CASE), "--over",
           "zeta=0.1:10:6:log", "-o", str(out), "--workers", "2", "-q"]
    proc = subprocess.Popen(cmd, start_new_session=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE)
    parts = Path(str(out) + ".parts")
    t0 = time.time()
    while len(list(parts.glob("point_*.nc"))) < 1 and time.time() - t0 < 120:
        time.sleep(0.05)
    os.killpg(proc.pid, signal.SIGKILL)  # the whole process group: driver and workers
    proc.wait()
    before = stats(parts)
    assert 1 <= len(before) < 6, before  # killed midway
    assert not out.exists()
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    after = stats(parts)
    assert len(after) == 6
    for name, st in before.items():  # finished points were neither recomputed nor rewritten
        assert after[name] == st, name
    assert_matches(read_dataset(out), ref6)
    # the last line says what the rerun reused and what it solved
    assert (f"; 6 points: {len(before)} kept from {out}.parts, {6 - len(before)} solved"
            in r.stdout), r.stdout
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)  # nothing left
    assert r.returncode == 0 and f"; 6 points: 6 kept from {out}.parts, 0 solved" in r.stdout


def crash_once(index, marker):
    """A sweep task that kills its worker process (as a worker killed mid-task) the first time
    it meets point ``index``, then solves as usual.  It is sent to the worker processes by
    value; there, ``sweep._run_point`` is the package's own."""
    def run(raw, base, overrides, i, digest, part):
        import os
        from pathlib import Path

        from spectralbem import sweep as s

        if i == index and not Path(marker).exists():
            Path(marker).touch()
            os._exit(17)
        return s._run_point(raw, base, overrides, i, digest, part)
    return run


def test_worker_crash_retried_and_truncated_file_recomputed(tmp_path, monkeypatch, ref6):
    out = tmp_path / "c.nc"
    marker = tmp_path / "crashed"
    over = [("zeta", ZETAS[:3])]
    with monkeypatch.context() as m:
        m.setattr(sweep, "_run_point", crash_once(1, str(marker)))
        run_sweep(CASE, over, out, workers=2, progress=False)
    assert marker.exists()  # the worker solving point 1 died once; dask retried the point
    ds = read_dataset(out)
    assert_matches(ds, ref6[:3])
    # truncate a finished point file and the final file: resume detects and recomputes
    parts = Path(str(out) + ".parts")
    p1 = parts / "point_00001.nc"
    before = stats(parts)
    data = p1.read_bytes()
    p1.write_bytes(data[: len(data) // 2])
    out.write_bytes(out.read_bytes()[:100])
    run_sweep(CASE, over, out, workers=1, progress=False)
    after = stats(parts)
    assert after["point_00000.nc"] == before["point_00000.nc"]
    assert after["point_00002.nc"] == before["point_00002.nc"]
    assert after["point_00001.nc"] != before["point_00001.nc"]
    xr.testing.assert_equal(read_dataset(out), ds)


def test_sweep_rejects_bad_points_before_solving(tmp_path):
    with pytest.raises(SceneError, match=r"point 1 .*sinusoid.zeta"):
        run_sweep(CASE, [("zeta", [0.1, -1.0])], tmp_path / "b.nc", progress=False)
    assert not (tmp_path / "b.nc.parts").exists()


def test_sweep_on_an_existing_scheduler(tmp_path, ref6):
    """--scheduler ADDRESS: the sweep runs on a cluster it did not start (and leaves it up)."""
    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address="127.0.0.1:0",
                      worker_dashboard_address="127.0.0.1:0") as cluster:
        out = run_sweep(CASE, [("zeta", ZETAS[4:])], tmp_path / "e.nc",
                        scheduler=cluster.scheduler_address, progress=False)
        assert len(cluster.scheduler.workers) == 1  # still up
    assert_matches(read_dataset(out), ref6[4:])


def test_sweep_dataset_records_the_scene_as_run_and_the_command(tmp_path):
    """The assembled dataset's ``scene`` holds the file with its --set values (a rerun needs
    them: it held the file alone) and ``history`` the command."""
    import json

    from spectralbem.sweep import run_sweep

    out = tmp_path / "g.nc"
    told = []
    path = run_sweep(CASE, [("zeta", [0.1, 1.0])], out, overrides={"sinusoid.Gamma": 0.05},
                     workers=1, progress=False, history="2026-11-28: spectralbem sweep test",
                     on_parts=lambda *a: told.append(a))
    ds = read_dataset(path)
    assert json.loads(ds.attrs["scene"])["sinusoid"]["Gamma"] == 0.05
    assert "spectralbem sweep test" in ds.attrs["history"]
    parts = Path(str(out) + ".parts")
    assert told == [(0, 2, parts)]  # on_parts: kept from earlier runs, to solve, the folder
    # the run's FFT attributes, as a point's file has them (fft_threads, read back as a numpy
    # integer, was dropped, and fft_planner not copied)
    point = read_dataset(parts / "point_00000.nc")
    for k in ("fft_backend", "fft_threads", "fft_planner"):
        assert ds.attrs[k] == point.attrs[k], k
    run_sweep(CASE, [("zeta", [0.1, 1.0])], out, overrides={"sinusoid.Gamma": 0.05},
              progress=False, on_parts=lambda *a: told.append(a))
    assert told[1] == (2, 0, parts)


def test_sweep_progress_on_a_pipe_is_plain_lines(tmp_path):
    """Without -q, a sweep whose stderr is a pipe (a log) shows plain progress lines, no
    tqdm bar: no carriage returns or escape codes."""
    out = tmp_path / "p.nc"
    cmd = [sys.executable, "-m", "spectralbem.cli", "sweep", str(CASE), "--over",
           "zeta=0.1,1.0", "-o", str(out), "--workers", "1"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "\r" not in r.stderr and "\x1b" not in r.stderr, repr(r.stderr)
    assert "sweep: 2/2 point" in r.stderr, r.stderr
    assert "; 2 points: 0 kept from" in r.stdout and ", 2 solved" in r.stdout, r.stdout


def test_strict_sweep_checks_every_point(tmp_path):
    """``--strict`` refuses a sweep on the plausibility warnings of its points (it checked the
    unswept base scene): the rough SLS case at 64² is plausible at its own speed here, a
    swept speed of 1e-6 m/s puts vτ = 1e-8 m far below two cells."""
    from spectralbem.schema import SceneError
    from spectralbem.sweep import run_sweep

    rough = Path(__file__).resolve().parent.parent / "cases" / "rough_convergence.toml"
    ov = {"grid.Nx": 64, "grid.Ny": 64, "surface.cutoff_wavelength": 2e-4,
          "adhesion.a0": 1.5625e-5, "motion.speed": 5e-3}
    with pytest.raises(SceneError, match=r"implausible \(--strict\), point 0: motion.speed"):
        run_sweep(rough, [("motion.speed", [1e-6, 1e-2])], tmp_path / "s.nc", overrides=ov,
                  strict=True, progress=False)
    assert not (tmp_path / "s.nc.parts").exists()  # refused before any work


def test_warnings_known_after_the_solves_reach_a_sweep(tmp_path):
    """The plausibility warning that only a solve can give (a0 against the small contact
    patches it found) is reported by a sweep as by `run`, and fails it with ``strict`` once
    its dataset is written (a worker's warnings were dropped: `sweep --strict` passed where
    `run --strict` failed on the same scene)."""
    jkr = CASE.parent / "jkr_sphere.toml"
    ov = {"grid.Nx": 64, "grid.Ny": 64, "adhesion.a0": 3.125e-5,
          "control.mean_pressure": [1e3, 5e2]}
    told = []
    path = run_sweep(jkr, [("dgamma", [0.05, 0.06])], tmp_path / "w.nc", overrides=ov,
                     workers=1, progress=False, on_warning=told.append)
    assert len(told) == 1 and told[0].startswith("point 0 (and 1 more): adhesion.a0: ")
    assert "small contact patches" in told[0]
    with pytest.raises(SceneError, match=r"implausible \(--strict, dataset written to "):
        run_sweep(jkr, [("dgamma", [0.05, 0.06])], tmp_path / "w.nc", overrides=ov,
                  workers=1, progress=False, strict=True)
    assert Path(path).is_file()
