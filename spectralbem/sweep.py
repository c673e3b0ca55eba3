"""Parameter sweeps on dask.distributed, persisted point by point and resumable.

``run_sweep(scene, [("zeta", values), ...], "out.nc")`` solves the Cartesian product of the
swept values (C order, the last ``--over`` varying fastest).  Every point is validated before
any solve.  Each finished point is written atomically to ``out.nc.parts/point_NNNNN.nc`` by the
worker that solved it, and its SHA-256 is recorded in ``out.nc.parts/manifest.json``; the
assembled ``out.nc`` is one Dataset with one dimension per swept key holding every scalar of
the points, and for a load/unload path every per-step variable on a ``step`` dimension after
the swept ones (fields are not kept in sweeps).

Resuming: a sweep killed at any moment and started again with the same command keeps every
point whose file matches its recorded checksum; a point file the driver did not get to record
is opened in a child process first (a corrupted netCDF file can crash netCDF-C) and kept when
it is a complete point of this sweep.  A point file that fails either check is named, moved
aside (``point_NNNNN.nc.corrupt``) and recomputed.  The sweep's digest covers the scene, the
overrides, the swept values, the contents of the files the scene refers to (height map,
modulus table, Δγ map) and the package version: a parts folder of another sweep is refused,
naming what changed.  One sweep at a time writes an output (a lock file in the parts folder);
temporary files left by killed runs are removed on start.  Ctrl-C stops the sweep, keeps the
finished points and says so (:class:`SweepInterrupted`).

The cluster is a local one (all cores, one thread per worker process) unless a scheduler
address is given.  Its scheduler, workers and nannies listen on the loopback interface only,
and its dashboard is off unless asked for (``dashboard=True``: on 127.0.0.1).  Anyone who can
connect to a dask scheduler can run code in its workers: give ``scheduler`` only the address
of a cluster on a trusted network (or reached through an SSH tunnel).  A point whose worker
dies is rescheduled by dask's scheduler (``distributed.scheduler.allowed-failures``); a point
whose solve raises is solved once and reported at the end; the finished ones stay on disk.
"""

from __future__ import annotations

import itertools
import json
import logging
import math
import os
import signal
import tempfile
import uuid
import warnings
from pathlib import Path
from types import SimpleNamespace

import numpy as np
from distributed.diagnostics.plugin import NannyPlugin, WorkerPlugin

from .io import (
    DiskFullError,
    _full_disk,
    cf_attributes,
    read_dataset,
    sha256_file,
    write_dataset,
)
from .plausibility import scene_warnings, state_warnings
from .scenes import apply_overrides, load_scene, read_scene_file
from .schema import SceneError, input_paths, section_keys
from .sweep_parts import (  # noqa: F401  (SweepError is part of this module's interface)
    SweepError,
    _check_parts,
    _clean_temporaries,
    _Lock,
    _Manifest,
    _say,
)

#: dimensions a point keeps (the path's steps); variables on any other dimension are fields
POINT_DIMS = {"step"}

__all__ = ["run_sweep", "parse_over", "SweepInterrupted"]


class SweepInterrupted(KeyboardInterrupt):
    """Ctrl-C during a sweep: ``kept`` of ``total`` points are on disk."""

    def __init__(self, kept: int, total: int):
        super().__init__(f"{kept}/{total} points kept; rerun the same command to resume")
        self.kept, self.total = kept, total


#: the most points a sweep may have (all ``--over`` axes together): a larger study is split
#: into several sweeps (each point is a dataset on disk before the sweep is assembled)
MAX_POINTS = 100_000


def parse_over(text: str):
    """``KEY=START:STOP:NUM[:log|lin]`` or ``KEY=V1,V2,...`` → (key, list of floats)."""
    if "=" not in text:
        raise SceneError(f"--over {text!r}: expected KEY=START:STOP:NUM[:log] or KEY=V1,V2")
    key, spec = (s.strip() for s in text.split("=", 1))
    try:
        if ":" in spec:
            parts = spec.split(":")
            if len(parts) not in (3, 4) or (len(parts) == 4 and parts[3] not in ("log", "lin")):
                raise ValueError("expected START:STOP:NUM[:log|lin]")
            a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
            if not 1 <= n <= MAX_POINTS:
                raise ValueError(f"NUM = {n} is outside [1, {MAX_POINTS}]")
            if len(parts) == 4 and parts[3] == "log":
                if a <= 0 or b <= 0:
                    raise ValueError("log spacing needs START, STOP > 0")
                values = np.geomspace(a, b, n)
            else:
                values = np.linspace(a, b, n)
        else:  # a whole number as written stays exact (a seed above 2**53)
            values = [int(v) if v.strip().lstrip("+-").isdigit() else float(v)
                      for v in spec.split(",")]
    except ValueError as exc:
        raise SceneError(f"--over {text!r}: {exc}") from exc
    if not all(math.isfinite(v) for v in values):
        raise SceneError(f"--over {text!r}: values must be finite")
    return key, [v if isinstance(v, int) else float(v) for v in values]


def _check_axes(keys: list, over: list, workers) -> None:
    """The sweep's axes and workers before any point is built: each key swept once, at most
    :data:`MAX_POINTS` points, at least one worker."""
    dup = sorted({k for k in keys if keys.count(k) > 1})
    if dup:
        raise SceneError(f"--over: {', '.join(dup)} swept more than once (one --over per key)")
    for k, (_, values) in zip(keys, over, strict=True):
        values = list(values)  # a numpy array of values too (the Python API's)
        twice = sorted({v for v in values if values.count(v) > 1})
        if twice:  # each would be solved again, and the axis would not index the points
            raise SceneError(f"--over {k}: {', '.join(f'{v:g}' for v in twice)} given more "
                             "than once (each value once)")
    n = int(np.prod([len(v) for _, v in over], dtype=float))
    if n > MAX_POINTS:
        raise SceneError(f"--over: {n:.3g} points ({' × '.join(str(len(v)) for _, v in over)})"
                         f" is more than {MAX_POINTS}; split the study into several sweeps")
    if workers is not None and workers < 1:
        raise SceneError(f"--workers: {workers} must be >= 1 (default: all cores)")


def _typed(raw: dict, key: str, value):
    """A swept value as its key's type: a whole number for an integer key (``surface.seed``,
    ``grid.Nx``), refused if it is not one; a float otherwise."""
    sec, name = key.split(".", 1)
    spec = section_keys(raw, sec).get(name)
    if spec is not None and spec.type == "integer":
        if not float(value).is_integer():
            raise SceneError(f"--over {key}: {value:g} is not a whole number")
        return int(value)
    return float(value)


def resolve_key(raw: dict, key: str) -> str:
    """A swept key as 'section.key': a bare name is looked up in the scene's sections."""
    if "." in key:
        return key
    hits = [f"{sec}.{key}" for sec in raw if key in section_keys(raw, sec)]
    if len(hits) != 1:
        raise SceneError(f"--over {key}: " + ("not a key of this scene" if not hits else
                                               f"ambiguous ({', '.join(hits)})")
                         + "; give it as section.key")
    return hits[0]


def _units(raw: dict, dotted: str) -> str:
    sec, key = dotted.split(".", 1)
    k = section_keys(raw, sec).get(key)
    return (k.units or "1") if k is not None else "1"


def input_files(raw: dict, overrides: dict | None, base) -> dict:
    """``{"section.key": sha256 of the file}`` for every file the scene refers to."""
    return {k: sha256_file(p) if p.is_file() else "not a regular file"
            for k, p in input_paths(apply_overrides(raw, overrides), base).items()}


def _digest(raw: dict, overs: list, overrides: dict | None, inputs: dict, version: str) -> str:
    import hashlib

    blob = json.dumps({"scene": raw, "over": overs, "set": overrides or {}, "inputs": inputs,
                       "version": version}, sort_keys=True, default=str)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def _point_variables(ds):
    """The variables a sweep keeps of a solved point: those on no dimension or on ``step``."""
    return ds.drop_vars([v for v in ds.variables if not set(ds[v].dims) <= POINT_DIMS])


def _run_point(raw, base, overrides, index, digest, part):
    """Worker task: solve one point and persist it atomically; returns (part path, sha256,
    None), or (None, None, why) when the point failed.  A failure is returned, not raised:
    dask's ``retries`` would solve a point whose solve raises again, with the same outcome
    (a deterministic failure cost three solves); a worker that dies is rescheduled by the
    scheduler itself (``distributed.scheduler.allowed-failures``)."""
    import dask

    from .plausibility import PlausibilityWarning
    from .scenes import solve

    try:
        scene = load_scene(raw, overrides=overrides, base_dir=base)
        with warnings.catch_warnings():  # the driver reported them when it validated them
            warnings.simplefilter("ignore", PlausibilityWarning)
            ds = _point_variables(solve(scene))
        ds.attrs.update(sweep_index=index, sweep_digest=digest)
        # xarray asks dask for its scheduler when it writes: inside a worker that would open
        # a client back to the scheduler (one per worker, left unclosed when a sweep stops)
        with dask.config.set(scheduler="synchronous"):
            write_dataset(ds, part)
        return part, sha256_file(part), None
    except DiskFullError as exc:
        return None, None, str(exc)
    except Exception as exc:  # noqa: BLE001 (reported with the point at the sweep's end)
        return None, None, f"{type(exc).__name__}: {exc}"


class _IgnoreSigint(WorkerPlugin):
    """Worker plugin of a local cluster: Ctrl-C in the terminal reaches the whole process
    group; the driver handles it, a worker process (also one restarted after a crash) ignores
    it instead of printing a traceback."""

    name = "spectralbem-ignore-sigint"
    idempotent = True

    def setup(self, worker):
        _ignore_sigint()


class _NannyIgnoresSigint(NannyPlugin):
    """The same for the nannies of a local cluster (their workers, restarted after a crash,
    inherit the ignored SIGINT)."""

    name = "spectralbem-nanny-ignore-sigint"
    idempotent = True

    def setup(self, nanny):
        _ignore_sigint()


def _ignore_sigint() -> None:
    """SIGINT ignored in this process (a cluster's worker or nanny)."""
    try:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    except ValueError:  # not the main thread of the process
        pass


def _client(scheduler, workers, dashboard=False):
    """(client, cluster or None).  A local cluster listens on 127.0.0.1 only; its dashboard
    is off unless ``dashboard`` (then on 127.0.0.1)."""
    import dask
    from dask.distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    n = workers or os.cpu_count() or 1
    # a Ctrl-C while the cluster starts is recorded and stops the sweep once it is up (an
    # ignored one, inherited by the processes as they start, was lost: the sweep ran to its
    # end); the nannies and workers then ignore SIGINT (the plugins below)
    main = _main_thread()
    old = signal.getsignal(signal.SIGINT) if main else None
    pending = []
    if main:
        signal.signal(signal.SIGINT, lambda signum, frame: pending.append(signum))
    # dask adds the dashboard's fallback page to its global list of HTTP routes in place: a
    # copy without it, so that an earlier cluster of the process cannot turn it on here
    routes = [r for r in dask.config.get("distributed.scheduler.http.routes", [])
              if "missing_bokeh" not in r]
    try:
        with warnings.catch_warnings(), dask.config.set(
                {"distributed.scheduler.http.routes": routes}):
            # without the dashboard, the scheduler's HTTP server (health and metrics routes)
            # takes any free loopback port; with it, port 8787 or (busy) any other: the link
            # is printed, dask's warning about the busy port is not
            warnings.filterwarnings("ignore", message=r"Port \d+ is already in use")
            http = "127.0.0.1:8787" if dashboard else "127.0.0.1:0"
            cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                   host="127.0.0.1", dashboard_address=http,
                                   scheduler_kwargs={"dashboard": bool(dashboard)},
                                   silence_logs=logging.CRITICAL,
                                   local_directory=tempfile.gettempdir())
    except Exception:
        if pending:  # the Ctrl-C reached a starting nanny too
            raise KeyboardInterrupt from None
        raise
    finally:
        if main:
            signal.signal(signal.SIGINT, old)
    if pending:
        cluster.close()
        raise KeyboardInterrupt
    try:
        client = Client(cluster)
        client.register_plugin(_IgnoreSigint())
        client.register_plugin(_NannyIgnoresSigint())
    except BaseException:
        cluster.close()
        raise
    if dashboard:
        _say(f"dashboard at {client.dashboard_link}")
    return client, cluster


def _main_thread() -> bool:
    import threading

    return threading.current_thread() is threading.main_thread()


def _shutdown(client, cluster, futs) -> None:
    """Cancel what is left and stop the cluster, quietly and without another Ctrl-C."""
    main = _main_thread()
    old = signal.getsignal(signal.SIGINT) if main else None
    if main:
        signal.signal(signal.SIGINT, signal.SIG_IGN)
    quiet = [logging.getLogger(n) for n in ("distributed", "tornado", "asyncio")]
    levels = [lg.level for lg in quiet]
    try:
        for lg in quiet:
            lg.setLevel(logging.CRITICAL + 1)
        try:
            if futs:
                client.cancel(list(futs))
        except Exception:
            pass
        try:
            client.close(timeout=10)
        except Exception:
            pass
        if cluster is not None:
            try:
                cluster.close(timeout=20)
            except Exception:
                pass
    finally:
        for lg, lv in zip(quiet, levels, strict=True):
            lg.setLevel(lv)
        if main:
            signal.signal(signal.SIGINT, old)


def _assemble(files, names, keys, grids, raw, digest, version, history=None):
    """One Dataset of every point: dims (*swept, step) for a path, (*swept) otherwise."""
    import datetime as _dt

    import xarray as xr

    shape = tuple(len(g) for g in grids)
    dss = [read_dataset(f) for f in files]
    nstep = max(ds.sizes.get("step", 0) for ds in dss)
    path = nstep > 0
    order, meta, strings = {}, {}, set()
    for ds in dss:
        for v in ds.data_vars:
            order.setdefault(v, len(order))
            meta.setdefault(v, dict(ds[v].attrs))
            if ds[v].dtype.kind in "OUS":
                strings.add(v)
    tail = (nstep,) if path else ()
    data = {}
    for v in order:
        arr = np.empty((len(dss), *tail), dtype=object if v in strings else float)
        arr[...] = "" if v in strings else np.nan
        for i, ds in enumerate(dss):
            if v not in ds:
                continue
            vals = ds[v].values
            if path and "step" in ds[v].dims:
                arr[i, :vals.shape[0]] = vals
            else:
                arr[i] = vals.item() if vals.ndim == 0 else vals
        data[v] = arr.reshape(shape + tail)
    dims = tuple(names) + (("step",) if path else ())
    # an output named like a swept key (p_tilde swept, p_tilde solved) becomes <name>_solved
    variables = {(f"{v}_solved" if v in names else v): (dims, arr, meta[v])
                 for v, arr in data.items()}
    coords = {n: (n, np.asarray(g), {"units": _units(raw, k), "long_name": f"swept {k}"})
              for n, k, g in zip(names, keys, grids, strict=True)}
    if path:
        ref = next(ds for ds in dss if ds.sizes.get("step", 0) == nstep)
        coords["step"] = ("step", np.arange(nstep), dict(ref["step"].attrs) if "step" in ref
                          else {"units": "1", "long_name": "path step"})
        if "control_value" in ref.coords:
            cv = np.full((len(dss), nstep), np.nan)
            for i, ds in enumerate(dss):
                if "control_value" in ds.coords:
                    c = np.asarray(ds["control_value"].values, float).ravel()
                    cv[i, :c.size] = c
            same = np.all((cv == cv[0]) | (np.isnan(cv) & np.isnan(cv[0])))
            coords["control_value"] = ((("step",), cv[0]) if same else
                                       (dims, cv.reshape(shape + tail))) + (
                dict(ref["control_value"].attrs),)
    res = xr.Dataset(variables, coords=coords)
    first = dss[0]
    attrs = {k: first.attrs[k] for k in ("title", "model", "fft_backend", "fft_threads",
                                         "fft_planner", "conventions") if k in first.attrs}
    attrs.update(sweep_keys=json.dumps(keys), sweep_digest=digest,
                 scene=json.dumps(raw, default=str), spectralbem_version=version,
                 created_utc=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"))
    # numbers as read back from a point's file are numpy scalars (fft_threads: np.int64)
    res.attrs.update({k: v.item() if isinstance(v, np.generic) else v for k, v in attrs.items()
                      if isinstance(v, (str, int, float, np.integer, np.floating))})
    return cf_attributes(res, history=history)


def run_sweep(scene_file, over: list, out, *, overrides: dict | None = None,
              scheduler: str | None = None, workers: int | None = None,
              progress: bool = True, retries: int = 2, dashboard: bool = False,
              history: str | None = None, strict: bool = False, on_warning=None,
              on_parts=None):
    """Run (or resume) a sweep; returns the path of the assembled dataset.

    ``over``: list of (key, values); keys are 'section.key' or a bare name unique in the scene.
    ``dashboard``: serve the dask dashboard of the local cluster on 127.0.0.1 (default: off).
    ``history``: the CF history line of the command (the dataset's ``history``).
    Every point is validated first, with its plausibility warnings (each message once):
    ``strict`` refuses the sweep on them, else ``on_warning(text)`` (default
    :func:`warnings.warn`) reports them.
    ``on_parts(kept, todo, parts)``: told once the parts folder is checked, before any solve:
    the number of points kept from earlier runs, the number to solve now, and the folder.
    Raises :class:`SweepInterrupted` on Ctrl-C (finished points are kept).
    """
    from . import __version__

    out = Path(out).absolute()  # workers may run in another working directory
    raw = read_scene_file(scene_file)
    base = Path(scene_file).resolve().parent
    # the scene as run, the swept keys at their base: its sections (a layer --set gives)
    # name the bare keys and their types
    spec = apply_overrides(raw, overrides)
    keys = [resolve_key(spec, k) for k, _ in over]
    _check_axes(keys, over, workers)
    names = [k.split(".")[-1] for k in keys]
    if len(set(names)) != len(names):
        names = [k.replace(".", "_") for k in keys]
    grids = [[_typed(spec, k, x) for x in v] for k, (_, v) in zip(keys, over, strict=True)]
    points = [dict(zip(keys, combo, strict=True)) for combo in itertools.product(*grids)]
    # validate every point before any heavy work, with its plausibility warnings
    problems, implausible, kinds = [], {}, []
    for i, pt in enumerate(points):
        try:
            scene = load_scene(spec, overrides=pt, base_dir=base)
        except SceneError as exc:
            problems += [f"point {i} ({pt}): {p}" for p in exc.problems]
            continue
        for m in scene_warnings(scene):
            implausible.setdefault(m, i)
        # what the warnings after the solve read of a point's scene (not its heights)
        kinds.append(SimpleNamespace(adhesive=scene.adhesive, a0=scene.a0,
                                     viscoelastic=scene.viscoelastic))
    if problems:
        raise SceneError(problems)
    if implausible and strict:
        raise SceneError([f"implausible (--strict), point {i}: {m}"
                          for m, i in implausible.items()])
    for m, i in implausible.items():
        (on_warning or warnings.warn)(f"point {i} (and maybe others): {m}")
    folder = out.parent
    if not folder.is_dir() or not os.access(folder, os.W_OK):
        raise OSError(f"output folder {str(folder)!r} does not exist or is not writable")
    inputs = input_files(raw, overrides, base)
    overs = [[k, v] for k, v in zip(keys, grids, strict=True)]
    digest = _digest(raw, overs, overrides, inputs, __version__)
    parts = Path(str(out) + ".parts")
    try:
        parts.mkdir(exist_ok=True)
    except OSError as exc:
        full = _full_disk(exc, parts, 0, guess=False)
        if full is not None:
            raise full from exc
        raise
    files = [parts / f"point_{i:05d}.nc" for i in range(len(points))]
    with _Lock(parts / "lock", out):
        try:
            _clean_temporaries(parts, out)
            head = {"digest": digest, "keys": keys, "values": grids, "version": __version__,
                    "inputs": inputs}
            manifest = _Manifest.open(parts / "manifest.json", head)
            todo = _check_parts(files, manifest, digest)
            if on_parts is not None:
                on_parts(len(points) - len(todo), len(todo), parts)
            if todo:
                allpt = [{**(overrides or {}), **pt} for pt in points]
                _compute(todo, allpt, raw, base, digest, files, manifest, points, parts,
                         scheduler, workers, progress, retries, dashboard)
            res = _assemble(files, names, keys, grids, spec, digest, __version__, history)
            path = write_dataset(res, out)
            _late_warnings(res, kinds, len(names), path, strict, on_warning)
            return path
        except KeyboardInterrupt as exc:
            if isinstance(exc, SweepInterrupted):
                raise
            kept = sum(f.is_file() for f in files)
            raise SweepInterrupted(kept, len(points)) from None


def _late_warnings(res, kinds, nswept, path, strict, on_warning) -> None:
    """The plausibility warnings known only after the solves (:func:`state_warnings`: a0
    against the small contact patches found), each point's: reported once, the first point
    named with the number of others; with ``strict`` the sweep fails on them (its dataset
    written, as ``run --strict`` keeps its)."""
    if "small_patch_diameter" not in res:
        return
    import xarray as xr

    d = np.asarray(res["small_patch_diameter"].values, float).reshape(len(kinds), -1)
    found = [(i, m) for i, sc in enumerate(kinds) for m in state_warnings(
        sc, xr.Dataset({"small_patch_diameter": ("step", d[i])}))]
    if not found:
        return
    i, m = found[0]
    text = f"point {i}" + (f" (and {len(found) - 1} more)" if len(found) > 1 else "")
    if strict:
        raise SceneError([f"implausible (--strict, dataset written to {path}), {text}: {m}"])
    (on_warning or warnings.warn)(f"{text}: {m}")


def _compute(todo, allpt, raw, base, digest, files, manifest, points, parts, scheduler,
             workers, progress, retries, dashboard):
    """Solve the points ``todo`` on the cluster, recording each finished one."""
    failed = {}
    client, cluster = _client(scheduler, workers, dashboard)
    futs, bar = {}, None
    try:
        from dask.distributed import as_completed

        # keys of this run only: two sweeps of one scene on a shared scheduler had the same
        # keys, and dask merged the second's tasks into the first's (its points written to
        # the first one's parts folder)
        run = uuid.uuid4().hex
        futs = {client.submit(_run_point, raw, str(base), allpt[i], i, digest,
                              str(files[i]), key=f"sweep-{digest}-{run}-{i}", pure=False,
                              retries=retries): i for i in todo}
        if progress:  # a bar on a terminal, else plain lines (progress.progress_bar)
            from .progress import progress_bar

            bar = progress_bar(total=len(points), initial=len(points) - len(todo),
                               unit="point", desc="sweep")
        for fut in as_completed(futs):
            i = futs[fut]
            try:
                _, sha, why = fut.result()
            except Exception as exc:  # keep going (the task itself failed: a lost worker)
                sha, why = None, f"{type(exc).__name__}: {exc}"
            if why is not None:
                failed[i] = why
            else:
                manifest.record(i, sha)
                try:
                    manifest.save()
                except OSError:  # tried again at the end; unrecorded points are checked
                    pass
            if bar is not None:
                bar.update(1)
    except KeyboardInterrupt:
        if bar is not None:
            bar.close()
            bar = None
        _shutdown(client, cluster, futs)
        client = None
        try:
            manifest.save(force=True)
        except (OSError, KeyboardInterrupt):
            pass
        kept = sum(f.is_file() for f in files)
        raise SweepInterrupted(kept, len(points)) from None
    finally:
        if bar is not None:
            bar.close()
        if client is not None:
            _shutdown(client, cluster, ())
    try:
        manifest.save(force=True)
    except OSError as exc:
        if not failed:
            raise
        failed[-1] = f"the manifest was not updated: {exc}"
    if failed:
        lines = [f"point {i} ({points[i]}): {m}" if i >= 0 else m
                 for i, m in sorted(failed.items())]
        n = sum(i >= 0 for i in failed)
        raise SweepError(f"{n} of {len(points)} points failed (the others are kept in "
                         f"{parts}; rerun the same command to retry):\n  " + "\n  ".join(lines))
