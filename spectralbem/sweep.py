"""Parameter sweeps on dask.distributed, persisted point by point and resumable.

``run_sweep(scene, [("zeta", values), ...], "out.nc")`` solves the Cartesian product of the
swept values (C order, the last ``--over`` varying fastest).  Every point is validated before
any solve.  Each finished point is written atomically to ``out.nc.parts/point_NNNNN.nc`` by the
worker that solved it; a sweep killed at any moment and started again with the same command
skips every point whose file is complete (it is opened and checked: index and sweep digest),
recomputes missing, truncated or corrupted ones, and assembles ``out.nc``: one Dataset with one
dimension per swept key holding every scalar of the points (fields are not kept in sweeps).

The cluster is a local one (all cores, one thread per worker process) unless a scheduler
address is given.  A point whose worker dies is retried by dask (``retries``).  A point that
raises is reported at the end; the finished ones stay on disk.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import os
import tempfile
from pathlib import Path

import numpy as np

from .io import read_dataset, write_dataset
from .scenes import apply_overrides, load_scene, read_scene_file
from .schema import KINDS, SECTIONS, SceneError

#: test hook: "INDEX:MARKER" makes the worker solving point INDEX exit abruptly once
#: (creating MARKER), to check that dask retries the point on another worker
CRASH_ENV = "SPECTRALBEM_CRASH_ONCE"


class SweepError(RuntimeError):
    """A sweep could not complete; finished points are kept on disk."""


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
            if n < 1:
                raise ValueError(f"NUM = {n} must be >= 1")
            if len(parts) == 4 and parts[3] == "log":
                if a <= 0 or b <= 0:
                    raise ValueError("log spacing needs START, STOP > 0")
                values = np.geomspace(a, b, n)
            else:
                values = np.linspace(a, b, n)
        else:
            values = np.array([float(v) for v in spec.split(",")])
    except ValueError as exc:
        raise SceneError(f"--over {text!r}: {exc}") from exc
    if not np.all(np.isfinite(values)):
        raise SceneError(f"--over {text!r}: values must be finite")
    return key, [float(v) for v in values]


def resolve_key(raw: dict, key: str) -> str:
    """A swept key as 'section.key': a bare name is looked up in the scene's sections."""
    if "." in key:
        return key
    hits = []
    for sec in raw:
        spec = SECTIONS.get(sec)
        if spec is None and sec in KINDS:
            kind = raw[sec].get("kind") if isinstance(raw[sec], dict) else None
            spec = KINDS[sec].get(kind, {})
        if spec and key in spec:
            hits.append(f"{sec}.{key}")
    if len(hits) != 1:
        raise SceneError(f"--over {key}: " + ("not a key of this scene" if not hits else
                                               f"ambiguous ({', '.join(hits)})")
                         + "; give it as section.key")
    return hits[0]


def _units(raw: dict, dotted: str) -> str:
    sec, key = dotted.split(".", 1)
    spec = SECTIONS.get(sec)
    if spec is None and sec in KINDS and isinstance(raw.get(sec), dict):
        spec = KINDS[sec].get(raw[sec].get("kind"), {})
    k = (spec or {}).get(key)
    return (k.units or "1") if k is not None else "1"


def _digest(raw: dict, overs: list, overrides: dict | None) -> str:
    blob = json.dumps({"scene": raw, "over": overs, "set": overrides or {}}, sort_keys=True,
                      default=str)
    return hashlib.sha256(blob.encode()).hexdigest()[:16]


def _part_ok(path: Path, index: int, digest: str) -> bool:
    """A finished point file: readable, complete, and of this sweep."""
    if not path.is_file():
        return False
    try:
        ds = read_dataset(path)
    except Exception:  # truncated / corrupted netCDF
        return False
    return (ds.attrs.get("sweep_digest") == digest and int(ds.attrs.get("sweep_index", -1))
            == index and "status" in ds)


def _run_point(raw, base, overrides, index, digest, part):
    """Worker task: solve one point and persist it atomically; returns the part path."""
    crash = os.environ.get(CRASH_ENV)
    if crash:
        idx, marker = crash.split(":", 1)
        if int(idx) == index and not os.path.exists(marker):
            Path(marker).touch()
            os._exit(17)  # simulate a worker killed mid-task
    from .scenes import solve

    scene = load_scene(raw, overrides=overrides, base_dir=base)
    ds = solve(scene)
    ds = ds.drop_vars([v for v in ds.data_vars if ds[v].dims != ()])
    ds = ds.drop_vars([c for c in ds.coords])
    ds.attrs.update(sweep_index=index, sweep_digest=digest)
    write_dataset(ds, part)
    return part


def _client(scheduler, workers):
    from dask.distributed import Client, LocalCluster

    if scheduler:
        return Client(scheduler), None
    n = workers or os.cpu_count() or 1
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                           dashboard_address=":0", silence_logs=40,
                           local_directory=tempfile.gettempdir())
    return Client(cluster), cluster


def run_sweep(scene_file, over: list, out, *, overrides: dict | None = None,
              scheduler: str | None = None, workers: int | None = None,
              progress: bool = True, retries: int = 2):
    """Run (or resume) a sweep; returns the path of the assembled dataset.

    ``over``: list of (key, values); keys are 'section.key' or a bare name unique in the scene.
    """
    import xarray as xr

    from . import __version__

    out = Path(out)
    raw = read_scene_file(scene_file)
    base = Path(scene_file).resolve().parent
    keys = [resolve_key(raw, k) for k, _ in over]
    names = [k.split(".")[-1] for k in keys]
    if len(set(names)) != len(names):
        names = [k.replace(".", "_") for k in keys]
    grids = [list(v) for _, v in over]
    points = [dict(zip(keys, combo, strict=True)) for combo in itertools.product(*grids)]
    # validate every point before any heavy work
    problems = []
    for i, pt in enumerate(points):
        try:
            load_scene(apply_overrides(raw, overrides), overrides=pt, base_dir=base)
        except SceneError as exc:
            problems += [f"point {i} ({pt}): {p}" for p in exc.problems]
    if problems:
        raise SceneError(problems)
    folder = out.parent if str(out.parent) else Path(".")
    if not folder.is_dir() or not os.access(folder, os.W_OK):
        raise OSError(f"output folder {str(folder)!r} does not exist or is not writable")
    digest = _digest(raw, [[k, v] for k, v in zip(keys, grids, strict=True)], overrides)
    parts = Path(str(out) + ".parts")
    parts.mkdir(exist_ok=True)
    manifest = parts / "manifest.json"
    try:
        old = json.loads(manifest.read_text()) if manifest.exists() else None
    except (OSError, ValueError):
        old = None  # a damaged manifest is rewritten: the point files carry their own digest
    if old is not None and old.get("digest") != digest:
        raise SweepError(f"{parts} holds the points of a different sweep (digest "
                         f"{old.get('digest')} ≠ {digest}); remove it or choose another -o")
    if old is None:
        tmp = manifest.with_suffix(".tmp")
        tmp.write_text(json.dumps({"digest": digest, "keys": keys, "values": grids}))
        os.replace(tmp, manifest)
    files = [parts / f"point_{i:05d}.nc" for i in range(len(points))]
    todo = [i for i in range(len(points)) if not _part_ok(files[i], i, digest)]
    for i in todo:  # a partial or foreign file is never trusted
        if files[i].exists():
            files[i].unlink()
    failed = {}
    if todo:
        allpt = [{**(overrides or {}), **pt} for pt in points]
        client, cluster = _client(scheduler, workers)
        try:
            from dask.distributed import as_completed

            futs = {client.submit(_run_point, raw, str(base), allpt[i], i, digest,
                                  str(files[i]), key=f"sweep-{digest}-{i}", pure=False,
                                  retries=retries): i for i in todo}
            bar = None
            if progress:
                from tqdm import tqdm

                bar = tqdm(total=len(points), initial=len(points) - len(todo), unit="point",
                           desc="sweep")
            for fut in as_completed(futs):
                i = futs[fut]
                try:
                    fut.result()
                except Exception as exc:  # keep going: the other points still finish
                    failed[i] = f"{type(exc).__name__}: {exc}"
                if bar is not None:
                    bar.update(1)
            if bar is not None:
                bar.close()
        finally:
            client.close()
            if cluster is not None:
                cluster.close()
    if failed:
        lines = [f"point {i} ({points[i]}): {m}" for i, m in sorted(failed.items())]
        raise SweepError(f"{len(failed)} of {len(points)} points failed (the others are kept in "
                         f"{parts}; rerun the same command to retry):\n  " + "\n  ".join(lines))
    # assemble
    shape = tuple(len(g) for g in grids)
    first = read_dataset(files[0])
    data = {}
    for v in first.data_vars:
        dtype = object if first[v].dtype.kind in "OUS" else float
        data[v] = np.empty(len(points), dtype=dtype)
    attrs = {k: first.attrs[k] for k in ("title", "model", "fft_backend", "fft_threads",
                                         "conventions") if k in first.attrs}
    for i, f in enumerate(files):
        ds = first if i == 0 else read_dataset(f)
        for v in data:
            data[v][i] = ds[v].item() if v in ds else (np.nan if data[v].dtype == float else "")
    dims = tuple(names)
    # an output named like a swept key (p_tilde swept, p_tilde solved) becomes <name>_solved
    variables = {(f"{v}_solved" if v in names else v): (dims, arr.reshape(shape),
                                                        dict(first[v].attrs))
                 for v, arr in data.items()}
    coords = {n: (n, np.asarray(g), {"units": _units(raw, k), "long_name": f"swept {k}"})
              for n, k, g in zip(names, keys, grids, strict=True)}
    res = xr.Dataset(variables, coords=coords)
    import datetime as _dt

    attrs.update(sweep_keys=json.dumps(keys), sweep_digest=digest,
                 scene_file=json.dumps(raw, default=str), spectralbem_version=__version__,
                 created_utc=_dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"))
    res.attrs.update({k: v for k, v in attrs.items() if isinstance(v, (str, int, float))})
    return write_dataset(res, out)
