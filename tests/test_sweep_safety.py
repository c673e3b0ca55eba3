"""Sweeps that keep everything and expose nothing: load-path sweeps keep their variables,
corrupt point files are named and recomputed, the digest covers input files and the version,
one sweep per output, no temporary file followed or left behind, a full disk named, Ctrl-C
in one line, the local cluster on the loopback only, output files that respect the umask.

Most tests run the sweep driver on an in-process dask cluster (threads, ``--scheduler``);
those about the local cluster itself (sockets, Ctrl-C) start one.
"""

import errno
import fcntl
import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import spectralbem
import spectralbem.io as sio
from spectralbem import cli, sweep
from spectralbem.io import DiskFullError, probe_netcdf, read_dataset, write_dataset, write_text
from spectralbem.scenes import load_scene, solve
from spectralbem.sweep import SweepError, SweepInterrupted, run_sweep

ROOT = Path(__file__).resolve().parent.parent
JKR = ROOT / "cases" / "jkr_sphere.toml"
SEED1D = ROOT / "cases" / "seed_sinusoid_1d.toml"
# the reproducer: an adhesive sphere on a load path (two steps), 32² cells
PATH_SET = {"grid.Nx": 32, "grid.Ny": 32, "adhesion.a0": 6.25e-5,
            "control.mean_pressure": [1e3, 5e2]}
DGAMMAS = [0.05, 0.06, 0.07, 0.08]


@pytest.fixture(scope="module")
def scheduler():
    """An in-process dask cluster (one worker thread): the sweep driver runs unchanged."""
    from dask.distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address="127.0.0.1:0", scheduler_kwargs={"dashboard": False},
                      worker_dashboard_address="127.0.0.1:0", silence_logs=50) as cluster:
        yield cluster.scheduler_address


def path_reference(dgammas):
    """Each point of the load-path sweep solved in this process: the variables a sweep keeps."""
    out = []
    for d in dgammas:
        ds = solve(load_scene(JKR, overrides={**PATH_SET, "adhesion.dgamma": d}))
        out.append(ds[[v for v in ds.data_vars if set(ds[v].dims) <= {"step"}]])
    return out


def assert_path_sweep(ds, ref, dgammas):
    assert ds["status"].dims == ("dgamma", "step")
    assert ds.sizes == {"dgamma": len(dgammas), "step": 2}
    np.testing.assert_array_equal(ds["control_value"].values, [1e3, 5e2])
    for i, r in enumerate(ref):
        assert set(r.data_vars) <= set(ds.data_vars)
        for v in r.data_vars:
            got, want = ds[v].values[i], r[v].values
            if want.dtype.kind in "OUS":
                assert [str(s) for s in got] == [str(s) for s in want], v
            else:  # the same code on the same machine: bit-identical (nan == nan)
                np.testing.assert_array_equal(got, want, err_msg=v)


def stats(parts):
    return {p.name: (p.stat().st_ino, p.stat().st_mtime_ns) for p in parts.glob("point_*.nc")}


def flip(path, pos, bit=3):
    data = bytearray(path.read_bytes())
    data[pos % len(data)] ^= 1 << bit
    path.write_bytes(bytes(data))


@pytest.fixture(scope="module")
def ref_path():
    return path_reference(DGAMMAS)


def test_load_path_sweep_keeps_every_variable_and_resumes(tmp_path, scheduler, ref_path):
    out = tmp_path / "p.nc"
    run_sweep(JKR, [("dgamma", DGAMMAS[:2])], out, overrides=PATH_SET, scheduler=scheduler,
              progress=False)
    ds = read_dataset(out)
    assert_path_sweep(ds, ref_path[:2], DGAMMAS[:2])
    parts = Path(str(out) + ".parts")
    before = stats(parts)
    assert len(before) == 2
    manifest = json.loads((parts / "manifest.json").read_text())
    assert sorted(manifest["parts"]) == ["0", "1"]  # a checksum per finished point
    run_sweep(JKR, [("dgamma", DGAMMAS[:2])], out, overrides=PATH_SET, scheduler=scheduler,
              progress=False)
    assert stats(parts) == before  # nothing recomputed on the rerun
    xr.testing.assert_identical(read_dataset(out).drop_attrs(), ds.drop_attrs())


def test_interrupted_load_path_sweep_resumes_to_the_uninterrupted_result(
        tmp_path, scheduler, monkeypatch, ref_path):
    """Ctrl-C (SIGINT to the driver) while point 2 of 4 runs: the finished points are kept,
    and the same call resumes to the dataset of an uninterrupted sweep."""
    real = sweep._run_point

    def interrupting(raw, base, overrides, index, digest, part):
        if index == 2:
            os.kill(os.getpid(), signal.SIGINT)
            time.sleep(0.5)  # the driver stops while this point runs
        return real(raw, base, overrides, index, digest, part)

    monkeypatch.setattr(sweep, "_run_point", interrupting)
    out = tmp_path / "i.nc"
    over = [("dgamma", DGAMMAS)]
    with pytest.raises(SweepInterrupted) as e:
        run_sweep(JKR, over, out, overrides=PATH_SET, scheduler=scheduler, progress=False)
    parts = Path(str(out) + ".parts")
    kept = stats(parts)
    assert 1 <= e.value.kept == len(kept) < 4 and e.value.total == 4
    assert str(e.value) == f"{len(kept)}/4 points kept; rerun the same command to resume"
    assert not out.exists()
    monkeypatch.setattr(sweep, "_run_point", real)
    run_sweep(JKR, over, out, overrides=PATH_SET, scheduler=scheduler, progress=False)
    after = stats(parts)
    assert all(after[k] == v for k, v in kept.items())  # kept points were not recomputed
    full = run_sweep(JKR, over, tmp_path / "u.nc", overrides=PATH_SET, scheduler=scheduler,
                     progress=False)
    resumed, uninterrupted = read_dataset(out), read_dataset(full)
    assert resumed.attrs["sweep_digest"] == uninterrupted.attrs["sweep_digest"]
    xr.testing.assert_identical(resumed.drop_attrs(), uninterrupted.drop_attrs())
    assert_path_sweep(resumed, ref_path, DGAMMAS)


def test_corrupt_point_files_are_named_moved_aside_and_recomputed(tmp_path, scheduler,
                                                                  capsys):
    out = tmp_path / "c.nc"
    over = [("dgamma", DGAMMAS[:3])]
    run_sweep(JKR, over, out, overrides=PATH_SET, scheduler=scheduler, progress=False)
    good = read_dataset(out)
    parts = Path(str(out) + ".parts")
    before = stats(parts)
    p0, p1 = parts / "point_00000.nc", parts / "point_00001.nc"
    flip(p0, 4000)  # one bit of a recorded point: its checksum no longer matches
    # point 1 as a driver killed before recording it leaves it, but truncated
    m = json.loads((parts / "manifest.json").read_text())
    del m["parts"]["1"]
    (parts / "manifest.json").write_text(json.dumps(m))
    p1.write_bytes(p1.read_bytes()[:3000])
    capsys.readouterr()
    run_sweep(JKR, over, out, overrides=PATH_SET, scheduler=scheduler, progress=False)
    err = capsys.readouterr().err
    assert f"{p0} is unusable (its checksum differs" in err
    assert f"{p1} is unusable (" in err
    assert (parts / "point_00000.nc.corrupt").is_file()
    assert (parts / "point_00001.nc.corrupt").is_file()
    after = stats(parts)
    assert after["point_00002.nc"] == before["point_00002.nc"]
    assert after["point_00000.nc"] != before["point_00000.nc"]
    xr.testing.assert_identical(read_dataset(out).drop_attrs(), good.drop_attrs())


def test_netcdf_files_are_probed_in_a_child_process(tmp_path, monkeypatch):
    """Random bit flips in a point file: each one is read, or refused with a reason, in a
    child process; the caller survives whatever netCDF-C does with it."""
    src = tmp_path / "a.nc"
    write_dataset(xr.Dataset({"status": ((), "partial"), "x": (("step",), [1.0, 2.0])},
                             attrs={"sweep_index": 3, "sweep_digest": "abc"}), src)
    info, err = probe_netcdf([src])[str(src)]
    assert err is None and info["attrs"]["sweep_index"] == 3 and "status" in info["variables"]
    rng = np.random.default_rng(1)
    data = src.read_bytes()
    files = []
    for k in range(40):
        d = bytearray(data)
        d[int(rng.integers(len(d)))] ^= 1 << int(rng.integers(8))
        files.append(tmp_path / f"f{k}.nc")
        files[-1].write_bytes(bytes(d))
    files += [tmp_path / "missing.nc", Path(__file__)]
    res = probe_netcdf(files)
    assert set(res) == {str(f) for f in files}
    for info, err in res.values():
        assert (info is None) != (err is None) and (err is None or "\n" not in err)
    assert res[str(files[-1])][1] and res[str(files[-2])][1]
    # a crash of the reader (as netCDF-C segfaults on some corrupted files) names the file
    # and the others are still read
    monkeypatch.setattr(sio, "_CHILD", "import os, signal, sys\n"
                        "for i, p in enumerate(sys.argv[1:]):\n"
                        "    print('BEGIN', i, flush=True)\n"
                        "    if p.endswith('crash.nc'): os.kill(os.getpid(), signal.SIGSEGV)\n"
                        "    print('OK', i, '{\"attrs\": {}, \"variables\": []}', flush=True)\n")
    res = probe_netcdf([src, tmp_path / "crash.nc", files[0]])
    assert res[str(tmp_path / "crash.nc")] == (
        None, "reading it crashed the netCDF library (SIGSEGV)")
    assert res[str(src)][1] is None and res[str(files[0])][1] is None


def test_run_and_plot_refuse_a_crashing_netcdf_file_in_one_line(tmp_path, monkeypatch,
                                                                capsys):
    bad = tmp_path / "bad.nc"
    write_dataset(xr.Dataset({"heights": (("x", "y"), np.zeros((32, 32)))}), bad)
    monkeypatch.setattr(sio, "_CHILD", "import os, signal\nprint('BEGIN', 0, flush=True)\n"
                        "os.kill(os.getpid(), signal.SIGSEGV)\n")
    sio._CHECKED.clear()
    scene = tmp_path / "s.toml"
    scene.write_text('[grid]\nLx = 1e-3\nLy = 1e-3\nNx = 32\nNy = 32\n[surface]\n'
                     'kind = "file"\npath = "bad.nc"\n[material]\nkind = "elastic"\nE = 1e6\n'
                     '[control]\nmean_pressure = 1e3\n')
    assert cli.main(["run", str(scene), "-o", str(tmp_path / "r.nc"), "-q"]) == 1
    err = capsys.readouterr().err
    assert f"height map '{bad}' is not a readable netCDF file: reading it crashed the netCDF " \
           "library (SIGSEGV)" in err
    assert cli.main(["plot", str(bad)]) == 1
    err = capsys.readouterr().err
    assert err == (f"spectralbem plot: error: dataset '{bad}' is not a readable netCDF file: "
                   "reading it crashed the netCDF library (SIGSEGV)\n")
    sio._CHECKED.clear()


def test_relative_output_is_made_absolute_before_dispatch(tmp_path, scheduler, monkeypatch):
    seen = tmp_path / "seen"  # the task is serialized: it reports through a file
    real = sweep._run_point

    def recording(raw, base, overrides, index, digest, part):
        seen.write_text(part)
        return real(raw, base, overrides, index, digest, part)

    monkeypatch.setattr(sweep, "_run_point", recording)
    monkeypatch.chdir(tmp_path)
    path = run_sweep(SEED1D, [("zeta", [1.0])], "rel.nc", scheduler=scheduler,
                     progress=False)
    assert path == tmp_path / "rel.nc" and path.is_file()
    assert seen.read_text() == str(tmp_path / "rel.nc.parts" / "point_00000.nc")


def test_digest_covers_input_files_and_the_version(tmp_path, scheduler, monkeypatch):
    h = np.zeros((32, 32))
    h[16, 16] = 1e-6
    np.save(tmp_path / "h.npy", h)
    scene = tmp_path / "s.toml"
    scene.write_text('[grid]\nLx = 1e-3\nLy = 1e-3\nNx = 32\nNy = 32\n[surface]\n'
                     'kind = "file"\npath = "h.npy"\n[material]\nkind = "elastic"\nE = 1e6\n'
                     '[control]\nmean_pressure = 1e2\n')
    out = tmp_path / "d.nc"
    over = [("material.E", [1e6, 2e6])]
    run_sweep(scene, over, out, scheduler=scheduler, progress=False)
    head = json.loads(Path(str(out) + ".parts/manifest.json").read_text())
    assert head["version"] == spectralbem.__version__
    assert list(head["inputs"]) == ["surface.path"]
    h[16, 16] = 2e-6
    np.save(tmp_path / "h.npy", h)  # same name, new contents
    with pytest.raises(SweepError, match="the contents of surface.path changed"):
        run_sweep(scene, over, out, scheduler=scheduler, progress=False)
    h[16, 16] = 1e-6
    np.save(tmp_path / "h.npy", h)
    monkeypatch.setattr(spectralbem, "__version__", "99.0")
    with pytest.raises(SweepError, match=r"spectralbem \S+ → 99\.0"):
        run_sweep(scene, over, out, scheduler=scheduler, progress=False)


def test_one_sweep_per_output(tmp_path):
    out = tmp_path / "l.nc"
    parts = Path(str(out) + ".parts")
    parts.mkdir()
    fd = os.open(parts / "lock", os.O_RDWR | os.O_CREAT)
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        os.write(fd, b"4242\n")
        with pytest.raises(SweepError, match=r"another sweep \(pid 4242\) is writing"):
            run_sweep(SEED1D, [("zeta", [1.0])], out, progress=False)
    finally:
        os.close(fd)
    assert not (parts / "manifest.json").exists()  # the locked-out sweep touched nothing


def test_no_symlink_followed_and_stale_temporaries_removed(tmp_path, scheduler):
    victim = tmp_path / "victim"
    victim.write_text("precious")
    out = tmp_path / "t.nc"
    parts = Path(str(out) + ".parts")
    parts.mkdir()
    (parts / "manifest.tmp").symlink_to(victim)  # the old fixed temporary name
    stale = [parts / ".point_00000.nc.k1ll3d.tmp", parts / ".manifest.json.x2.tmp",
             tmp_path / ".t.nc.y3.tmp"]
    for s in stale:
        s.write_bytes(b"")
    (tmp_path / ".other.nc.z.tmp").write_bytes(b"")  # not this sweep's: left alone
    run_sweep(SEED1D, [("zeta", [1.0])], out, scheduler=scheduler, progress=False)
    assert victim.read_text() == "precious"
    assert not (parts / "manifest.tmp").is_symlink()
    assert not any(s.exists() for s in stale)
    assert (tmp_path / ".other.nc.z.tmp").exists()
    assert sorted(p.name for p in parts.iterdir()) == ["lock", "manifest.json",
                                                       "point_00000.nc"]


def test_full_disk_is_named_and_leaves_nothing(tmp_path, monkeypatch, capsys):
    ds = xr.Dataset({"a": ((), 1.0)})
    monkeypatch.setattr(sio, "_free_bytes", lambda folder: 0)
    for exc in (RuntimeError("NetCDF: HDF error"), PermissionError(13, "Permission denied")):
        def failing(*args, exc=exc, **kwargs):
            raise exc

        monkeypatch.setattr(xr.Dataset, "to_netcdf", failing)
        with pytest.raises(DiskFullError, match=f"cannot write '{tmp_path / 'x.nc'}': no space "
                                                "left on device") as e:
            write_dataset(ds, tmp_path / "x.nc")
        assert e.value.errno == errno.ENOSPC
    monkeypatch.setattr(sio, "_free_bytes", lambda folder: 10**12)
    with pytest.raises(PermissionError):  # with room on the disk: the error as it is
        write_dataset(ds, tmp_path / "x.nc")

    def no_space(fd):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(os, "fsync", no_space)
    with pytest.raises(DiskFullError, match="manifest.json': no space left on device"):
        write_text(tmp_path / "manifest.json", "{}")
    assert list(tmp_path.iterdir()) == []  # no temporary (0-byte or partial) left behind
    # the command line: one line naming the file
    monkeypatch.setattr(sio, "_free_bytes", lambda folder: 0)
    assert cli.main(["run", str(SEED1D), "-o", str(tmp_path / "r.nc"), "-q"]) == 1
    assert capsys.readouterr().err == (f"spectralbem run: error: cannot write "
                                       f"'{tmp_path / 'r.nc'}': no space left on device "
                                       "(0 bytes free)\n")


def test_full_disk_error_survives_the_trip_from_a_worker():
    import pickle

    e = pickle.loads(pickle.dumps(sio.disk_full("/x/p.nc", 0)))
    assert type(e) is DiskFullError and e.errno == errno.ENOSPC
    assert str(e) == "cannot write '/x/p.nc': no space left on device (0 bytes free)"


@pytest.mark.parametrize("mask", [0o022, 0o077, 0o002])
def test_output_files_respect_the_umask(tmp_path, mask):
    old = os.umask(mask)
    try:
        assert sio.umask() == mask
        p = write_dataset(xr.Dataset({"a": ((), 1.0)}), tmp_path / "a.nc")
        t = write_text(tmp_path / "m.json", "{}")
    finally:
        os.umask(old)
    for f in (p, t):
        assert f.stat().st_mode & 0o777 == 0o666 & ~mask


def test_no_crash_hook_in_the_package():
    for f in (ROOT / "spectralbem").glob("*.py"):
        text = f.read_text()
        assert "SPECTRALBEM_CRASH" not in text and "os._exit" not in text, f.name


def _listening(pids):
    import psutil

    found = []
    for pid in pids:
        try:
            conns = psutil.Process(pid).net_connections(kind="inet")
        except psutil.Error:
            continue
        found += [c.laddr for c in conns if c.status == psutil.CONN_LISTEN]
    return found


@pytest.mark.parametrize("dashboard", [False, True])
def test_local_cluster_listens_on_the_loopback_only(dashboard):
    import urllib.error
    import urllib.request

    import psutil

    me = psutil.Process()
    before = set(_listening([me.pid]))  # other tests' clusters in this process
    client, cluster = sweep._client(None, 1, dashboard=dashboard)
    try:
        pids = [me.pid] + [c.pid for c in me.children(recursive=True)]
        socks = [a for a in _listening(pids) if a not in before]
        assert len(socks) >= 4  # scheduler, its HTTP server, nanny, worker (and its HTTP)
        assert all(a.ip in ("127.0.0.1", "::1") for a in socks), socks
        link = client.dashboard_link
        assert link.startswith("http://127.0.0.1:")
        try:
            status = urllib.request.urlopen(link, timeout=10).status
        except urllib.error.HTTPError as exc:
            status = exc.code
        assert (status == 200) == dashboard  # the dashboard page exists only when asked for
        # Ctrl-C reaches every process of the terminal's group: the workers ignore it
        assert set(client.run(lambda: int(signal.getsignal(signal.SIGINT))).values()) == {
            int(signal.SIG_IGN)}
    finally:
        sweep._shutdown(client, cluster, ())


def test_ctrl_c_prints_one_line_and_the_same_command_resumes(tmp_path):
    """The command line under Ctrl-C (SIGINT to the whole process group, as a terminal
    sends it) during a load-path sweep of the 1D model: one line, exit code 130; the same
    command then finishes the sweep to the uninterrupted result."""
    out = tmp_path / "k.nc"
    zetas = [0.1, 0.3, 1.0, 3.0, 10.0, 30.0]
    cmd = [sys.executable, "-m", "spectralbem.cli", "sweep", str(SEED1D), "--set",
           "sinusoid.p_tilde=[0.1, 0.2]", "--over", "zeta=" + ",".join(map(str, zetas)),
           "-o", str(out), "--workers", "2", "-q"]
    proc = subprocess.Popen(cmd, start_new_session=True, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    parts = Path(str(out) + ".parts")
    t0 = time.time()
    while not list(parts.glob("point_*.nc")) and time.time() - t0 < 120:
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    kept = len(list(parts.glob("point_*.nc")))
    assert proc.returncode == 130, err
    assert err == (f"spectralbem sweep: interrupted: {kept}/6 points kept; rerun the same "
                   "command to resume\n")
    assert 1 <= kept < 6
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    ds = read_dataset(out)
    assert ds["a_tilde"].dims == ("zeta", "step")
    for i, z in enumerate(zetas):
        ref = solve(load_scene(SEED1D, overrides={"sinusoid.zeta": z,
                                                  "sinusoid.p_tilde": [0.1, 0.2]}))
        for v in ("a_tilde", "e_tilde", "mu_bar", "G1_over_dgamma", "status"):
            np.testing.assert_array_equal(ds[v].values[i], ref[v].values, err_msg=v)


def test_a_failing_point_is_solved_once(tmp_path, scheduler, monkeypatch):
    """A point whose solve raises is reported after one solve: dask's ``retries`` re-ran any
    task that raised, so a deterministic failure cost three solves before it was named."""
    import spectralbem.scenes as scenes

    calls = []

    def failing(scene, **kw):
        calls.append(1)
        raise RuntimeError("deterministic failure")

    monkeypatch.setattr(scenes, "solve", failing)
    with pytest.raises(SweepError, match="point 0 .*RuntimeError: deterministic failure"):
        run_sweep(SEED1D, [("zeta", [0.1])], tmp_path / "f.nc", scheduler=scheduler,
                  progress=False)
    assert len(calls) == 1


def test_two_sweeps_of_one_scene_have_their_own_task_keys(tmp_path, scheduler, monkeypatch):
    """The task keys of a sweep are its run's own: keys made of the sweep's digest and the
    point's index were the same for two identical sweeps to different outputs, and on one
    shared scheduler at once dask merged the second's tasks into the first's (the second
    failed: its points were written to the first one's parts folder)."""
    from distributed import Client

    keys, submit = [], Client.submit

    def spy(self, *args, key=None, **kw):
        keys.append(key)
        return submit(self, *args, key=key, **kw)

    monkeypatch.setattr(Client, "submit", spy)
    for name in ("a.nc", "b.nc"):
        run_sweep(SEED1D, [("zeta", [0.1, 0.2])], tmp_path / name, scheduler=scheduler,
                  progress=False)
    assert len(keys) == 4 and len(set(keys)) == 4, keys
    xr.testing.assert_identical(read_dataset(tmp_path / "a.nc").drop_attrs(),
                                read_dataset(tmp_path / "b.nc").drop_attrs())


def _children(pid: int) -> list:
    """The processes whose parent is ``pid`` (from /proc)."""
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            out.append(int(stat.parent.name))
    return out


def test_ctrl_c_while_the_local_cluster_starts_stops_the_sweep(tmp_path):
    """Ctrl-C to the sweep driver while its local cluster starts (its first child process
    exists, no point is solved yet): the sweep stops with its one line and exit 130 (the
    driver ignored SIGINT during the start-up, so that the workers would inherit the
    ignore, and the sweep ran to its end with exit 0)."""
    out = tmp_path / "s.nc"
    cmd = [sys.executable, "-m", "spectralbem.cli", "sweep", str(SEED1D), "--over",
           "zeta=0.1,0.2,0.3,0.4,0.5,0.6", "-o", str(out), "--workers", "2", "-q"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.time()
    while not _children(proc.pid) and proc.poll() is None and time.time() - t0 < 60:
        time.sleep(0.02)
    os.kill(proc.pid, signal.SIGINT)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 130, err
    assert err.splitlines()[-1].startswith("spectralbem sweep: interrupted"), err
    assert not out.exists()
