"""Command line: ``spectralbem run | sweep | refine | plot | validate | info``.

Examples::

    spectralbem run cases/rubber_rough.toml -o rubber.nc
    spectralbem run cases/jkr_sphere.toml -o jkr.nc --set grid.Nx=128 --set grid.Ny=128
    spectralbem sweep cases/seed_sinusoid_1d.toml --over zeta=1e-3:1e2:25:log -o fig5.nc
    spectralbem refine cases/rubber_rough.toml --sizes 128 256 512 -o refine.nc
    spectralbem plot rubber.nc -o rubber.png
    spectralbem validate --quick
    spectralbem info

Every command exits non-zero with a one-line reason (scene problems: one line each) on failure.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path


def _info(args) -> int:
    import platform
    from importlib import metadata

    from . import __version__, fft, kernels

    def version(dist):
        try:
            return metadata.version(dist)
        except metadata.PackageNotFoundError:
            return "not installed"

    print(f"spectralbem {__version__}")
    print(f"python {platform.python_version()}, " + ", ".join(
        f"{d} {version(d)}" for d in ("numpy", "scipy", "xarray", "netCDF4", "dask",
                                      "distributed", "numba", "pyFFTW", "matplotlib")))
    from . import backend

    print(f"compute backend: {backend.get().name} (SPECTRALBEM_BACKEND; available: "
          f"{', '.join(backend.names())})")
    print(f"FFT backend: {fft.backend()}, threads: {fft.get_threads()}")
    print(f"compiled loops: {kernels.backend()} (SPECTRALBEM_JIT=0 selects the numpy twins)")
    return 0


def _plausible(scene, strict: bool) -> None:
    """Print the scene's plausibility warnings (stderr) before any solve; ``--strict``: stop
    with them as the error."""
    from .plausibility import scene_warnings
    from .schema import SceneError

    msgs = scene_warnings(scene)
    if msgs and strict:
        raise SceneError(["implausible (--strict): " + m for m in msgs])
    for m in msgs:
        print(f"warning: {m}", file=sys.stderr)


def _history(argv) -> str:
    """A CF history line: UTC time and the command's arguments as given."""
    import datetime
    import shlex

    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    return f"{now}: spectralbem {shlex.join(str(a) for a in argv)}"


def _overrides(items) -> dict:
    from .scenes import parse_value
    from .schema import SceneError

    out = {}
    for item in items or []:
        if "=" not in item:
            raise SceneError(f"--set {item!r}: expected section.key=VALUE")
        k, v = item.split("=", 1)
        out[k.strip()] = parse_value(v.strip())
    return out


#: the suffix of the datasets ``run``, ``sweep`` and ``refine`` write (netCDF)
DATASET_SUFFIXES = (".nc",)
DATASET_HINT = " (the output is a netCDF dataset; draw it with spectralbem plot)"


def _image_suffixes() -> tuple:
    """The suffixes ``plot -o`` can write (matplotlib's formats)."""
    from matplotlib.backend_bases import FigureCanvasBase

    return tuple(sorted(f".{k}" for k in FigureCanvasBase.get_supported_filetypes()))


def _check_output(path: Path, inputs=(), suffixes=(), hint: str = ""):
    """Before any heavy work: the output's folder exists and is writable, and the output is
    not an existing folder, device or pipe, nor one of the command's ``inputs``; with
    ``suffixes``, its suffix is one of them (any case; ``hint`` ends the message)."""
    import os

    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise OSError(f"output folder {str(folder)!r} does not exist")
    if not os.access(folder, os.W_OK):
        raise OSError(f"output folder {str(folder)!r} is not writable")
    if path.exists() and not path.is_file():
        raise OSError(f"output {str(path)!r} exists and is not a regular file (a folder, "
                      "device or pipe); give a file name")
    for f in inputs:
        if path.exists() and Path(f).exists() and path.samefile(f):
            raise OSError(f"output {str(path)!r} is the input {str(f)!r}; give another name")
    if suffixes and path.suffix.lower() not in suffixes:
        got = f"the suffix {path.suffix!r}" if path.suffix else "no suffix"
        raise ValueError(f"-o {str(path)!r} has {got}; allowed suffix"
                         f"{'es' if len(suffixes) > 1 else ''}: {', '.join(suffixes)}{hint}")


def _inputs(scene_path, overrides=None) -> list:
    """The scene file and every file it reads (a height map, a modulus table, a Δγ map):
    what an output must not overwrite.  A scene that does not parse gives the scene file
    alone (its loader reports the problems)."""
    from .scenes import apply_overrides, read_scene_file
    from .schema import input_paths

    try:
        spec = apply_overrides(read_scene_file(scene_path), overrides)
        files = input_paths(spec, Path(scene_path).resolve().parent)
    except Exception:  # noqa: BLE001 (the scene's own loader says what is wrong)
        files = {}
    return [Path(scene_path), *files.values()]


def _run(args) -> int:
    from .io import STATUS_MEANING, cf_attributes, write_dataset
    from .plausibility import PlausibilityWarning, state_warnings
    from .scenes import load_scene, solve
    from .schema import SceneError
    from .solving import REPORTED, PathInterrupted

    out = Path(args.output)
    _check_output(out, _inputs(args.scene, _overrides(args.set)), DATASET_SUFFIXES,
                  DATASET_HINT)  # before any heavy work
    scene = load_scene(args.scene, overrides=_overrides(args.set))
    _plausible(scene, args.strict)
    t = time.perf_counter()
    try:
        with warnings.catch_warnings():  # printed above
            warnings.simplefilter("ignore", PlausibilityWarning)
            ds = solve(scene, progress=not args.quiet)
    except PathInterrupted as exc:  # Ctrl-C on a load path: the finished steps are kept
        cf_attributes(exc.dataset, history=_history(args.argv))
        write_dataset(exc.dataset, out)
        print(f"spectralbem run: interrupted: {exc} (kept in {out})", file=sys.stderr)
        return 130
    ds.attrs["wall_time_s"] = time.perf_counter() - t
    cf_attributes(ds, history=_history(args.argv))
    write_dataset(ds, out)
    late = state_warnings(scene, ds)  # known only after the solve (the patches found)
    if late and args.strict:  # the dataset is kept; the command fails
        raise SceneError([f"implausible (--strict, dataset written to {out}): " + m
                          for m in late])
    for m in late:
        print(f"warning: {m}", file=sys.stderr)
    status = ds["status"].values.ravel()
    seen = dict.fromkeys(str(s) for s in status)
    print(f"{Path(args.scene).name}: model {ds.attrs['model']}, status "
          + ", ".join(f"{s} ({STATUS_MEANING.get(s, s)})" for s in seen)
          + f", {ds.attrs['wall_time_s']:.2f} s -> {out}")
    return 0 if all(s in REPORTED for s in status) else 2


def _sweep(args) -> int:
    from .sweep import SweepInterrupted, parse_over, run_sweep

    out = Path(args.output)
    _check_output(out, _inputs(args.scene, _overrides(args.set)), DATASET_SUFFIXES,
                  DATASET_HINT)
    over = [parse_over(o) for o in args.over]
    t = time.perf_counter()
    counts = {}

    def parts_checked(kept, todo, parts):  # named as the command line gave -o
        counts.update(kept=kept, todo=todo, parts=f"{out}.parts")

    try:
        path = run_sweep(args.scene, over, out, overrides=_overrides(args.set),
                         scheduler=args.scheduler, workers=args.workers,
                         progress=not args.quiet, dashboard=args.dashboard,
                         history=_history(args.argv), strict=args.strict,
                         on_warning=lambda m: print(f"warning: {m}", file=sys.stderr),
                         on_parts=parts_checked)
    except SweepInterrupted as exc:  # Ctrl-C: one line, the finished points are on disk
        print(f"spectralbem sweep: interrupted: {exc}", file=sys.stderr)
        return 130
    bad, total = _unverified(path)
    print(f"sweep of {Path(args.scene).name} finished in {time.perf_counter() - t:.1f} s "
          f"-> {path}" + _sweep_counts(counts)
          + (f"; {bad} of {total} states not verified (not_converged: their "
             f"messages are in {path}.parts/)" if bad else ""))
    return 2 if bad else 0


def _sweep_counts(counts: dict) -> str:
    """``; n points: k kept from OUT.nc.parts, m solved`` (what a rerun reused)."""
    if not counts:
        return ""
    n = counts["kept"] + counts["todo"]
    return (f"; {n} point{'s' if n != 1 else ''}: {counts['kept']} kept from "
            f"{counts['parts']}, {counts['todo']} solved")


def _unverified(path) -> tuple:
    """(states not verified, states) of a written dataset (a sweep's points and steps)."""
    import numpy as np
    import xarray as xr

    from .solving import REPORTED

    with xr.open_dataset(path) as ds:
        if "status" not in ds:
            return 0, 0
        status = [str(x) for x in np.ravel(ds["status"].values)]
    return sum(x not in REPORTED for x in status), len(status)


def _refine(args) -> int:
    from .plausibility import PlausibilityWarning, state_warnings
    from .refinement import VERIFIED, refine, resolution_overrides, summary
    from .scenes import load_scene, read_scene_file
    from .schema import SceneError

    out = Path(args.output)
    ov = _overrides(args.set)
    _check_output(out, _inputs(args.scene, ov), DATASET_SUFFIXES, DATASET_HINT)
    per_size = resolution_overrides(read_scene_file(args.scene), ov, args.sizes,
                                    args.a0_cells, Path(args.scene).resolve().parent)
    _plausible(load_scene(args.scene, overrides=per_size[-1]), args.strict)

    def tell(i, n, text):
        if not args.quiet:
            print(f"[{i + 1}/{len(args.sizes)}] N = {n}: {text}", file=sys.stderr, flush=True)

    try:
        with warnings.catch_warnings():  # printed above, for the finest grid
            warnings.simplefilter("ignore", PlausibilityWarning)
            ds = refine(args.scene, args.sizes, out, overrides=ov, a0_cells=args.a0_cells,
                        progress=tell, history=_history(args.argv))
    except KeyboardInterrupt:  # the finished grids are on disk
        parts = out.with_name(out.name + ".parts")
        kept = len(list(parts.glob("N_*.nc"))) if parts.is_dir() else 0
        print(f"spectralbem refine: interrupted: {kept} grid(s) kept in {parts}; rerun the "
              "same command to resume", file=sys.stderr)
        return 130
    late = [f"N = {n}: {m}" for n, o in zip(sorted(args.sizes), per_size, strict=True)
            for m in state_warnings(load_scene(args.scene, overrides=o), ds.sel(N=n))]
    if late and args.strict:  # known only after the solves; the dataset is kept
        raise SceneError([f"implausible (--strict, dataset written to {out}): " + m
                          for m in late])
    for m in late:
        print(f"warning: {m}", file=sys.stderr)
    print(summary(ds))
    print(f"refinement of {Path(args.scene).name} over N = "
          f"{', '.join(str(int(n)) for n in ds['N'].values)} in "
          f"{ds.attrs['wall_time_s']:.1f} s -> {out}")
    status = [str(x) for x in ds["status"].values.ravel()]
    return 0 if all(x in (*VERIFIED, "detached") for x in status) else 2


def _plot(args) -> int:
    from .io import read_dataset
    from .plotting import plot_dataset

    path = Path(args.dataset)
    if not path.is_file():
        raise FileNotFoundError(f"dataset {str(path)!r} " + (
            "is not a file" if path.exists() else "does not exist"))
    ds = read_dataset(path, verify=True)  # a corrupted file must not crash netCDF-C here
    if args.step is not None:
        n = ds.sizes.get("step", 0)
        if not n:
            raise ValueError(f"--step: {args.step} given but {path.name} is not a path "
                             "(no step dimension)")
        if not -n <= args.step < n:
            raise ValueError(f"--step: {args.step} is outside the path's steps "
                             f"[0, {n - 1}] (negative counts from the end)")
        ds = ds.isel(step=args.step)
    out = Path(args.output) if args.output else path.with_suffix(".png")
    _check_output(out, [path], _image_suffixes())  # before rendering
    plot_dataset(ds, out)
    print(f"wrote {out}")
    return 0


def _validate(args) -> int:
    import shlex

    from .validate import main as vmain

    try:
        vmain((["--quick"] if args.quick else []) + ["-o", str(args.output)],
              command=f"spectralbem {shlex.join(args.argv)}")
    except SystemExit as exc:  # validate reports a failed tolerance this way
        if exc.code not in (None, 0):
            raise RuntimeError(str(exc.code)) from None
    return 0


EXAMPLES = {
    "run": "spectralbem run cases/rubber_rough.toml -o rubber.nc\n"
           "  spectralbem run cases/jkr_sphere.toml -o jkr.nc --set grid.Nx=128 "
           "--set grid.Ny=128",
    "sweep": "spectralbem sweep cases/seed_sinusoid_1d.toml --over zeta=1e-3:1e2:25:log "
             "-o fig5.nc\n  spectralbem sweep cases/rubber_rough.toml --over "
             "motion.speed=1e-4,1e-3,1e-2 --over control.mean_pressure=5e3:2e4:4 -o s.nc",
    "refine": "spectralbem refine cases/rubber_rough.toml --sizes 128 256 512 -o refine.nc\n"
              "  spectralbem plot refine.nc",
    "plot": "spectralbem plot rubber.nc -o rubber.png",
    "validate": "spectralbem validate --quick",
    "info": "spectralbem info",
}


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="spectralbem", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)

    def cmd(name, help_, desc):
        return sub.add_parser(name, help=help_, description=f"{desc}\n\nexamples:\n  "
                              f"{EXAMPLES[name]}",
                              formatter_class=argparse.RawDescriptionHelpFormatter)

    p = cmd("run", "solve one scene file", "Solve a scene (TOML) and write a netCDF dataset. "
            "Exit code 2 when a state did not converge (the dataset is still written).")
    p.add_argument("scene", help="scene file (TOML); see docs/user_guide.md")
    p.add_argument("-o", "--output", required=True, help="netCDF output path (.nc)")
    p.add_argument("--set", action="append", metavar="SECTION.KEY=VALUE",
                   help="override a scene value (repeatable)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.add_argument("--strict", action="store_true",
                   help="stop on plausibility warnings (large p/E*, steep or tall surface, "
                        "modulus table not covering q·v, a0 large against the cut-off)")
    p.set_defaults(func=_run)
    p = cmd("sweep", "sweep a scene over parameters (dask, resumable)",
            "Solve a scene over the Cartesian product of swept values on dask.distributed "
            "(a local cluster on all cores, listening on 127.0.0.1 only, or --scheduler). "
            "Each finished point is kept in OUT.parts/; rerunning the same command (also "
            "after Ctrl-C, exit code 130) resumes.")
    p.add_argument("scene", help="scene file (TOML)")
    p.add_argument("--over", action="append", required=True,
                   metavar="KEY=START:STOP:NUM[:log]|KEY=V1,V2,...",
                   help="swept key (section.key, or a bare key unique in the scene); "
                        "repeatable")
    p.add_argument("-o", "--output", required=True, help="netCDF output path (.nc)")
    p.add_argument("--set", action="append", metavar="SECTION.KEY=VALUE",
                   help="override a scene value (repeatable)")
    p.add_argument("--scheduler", help="address of an existing dask scheduler (anyone who can "
                   "connect to it can run code in its workers: a trusted network or an SSH "
                   "tunnel only)")
    p.add_argument("--dashboard", action="store_true",
                   help="serve the local cluster's dask dashboard on 127.0.0.1 (default: off)")
    p.add_argument("--workers", type=int, help="local workers (default: all cores)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    p.add_argument("--strict", action="store_true",
                   help="stop on plausibility warnings (large p/E*, steep or tall surface, "
                        "modulus table not covering q·v, a0 large against the cut-off)")
    p.set_defaults(func=_sweep)
    p = cmd("refine", "solve a scene on finer and finer grids (same physical surface)",
            "Solve a scene at each resolution of --sizes (grid.Nx, grid.Ny in proportion; "
            "the seed's 2D scene: sinusoid.cells_per_wavelength) with every physical length "
            "kept, and estimate each output's grid error by Richardson extrapolation from "
            "the three finest grids (none where the changes do not shrink yet). Each "
            "finished grid is kept in OUT.parts/; rerunning the same command resumes. Exit "
            "code 2 when a state did not converge.")
    p.add_argument("scene", help="scene file (TOML) with a generated surface")
    p.add_argument("--sizes", type=int, nargs="+", required=True, metavar="N",
                   help="resolutions, growing by a constant ratio (e.g. 128 256 512)")
    p.add_argument("-o", "--output", required=True, help="netCDF output path (.nc)")
    p.add_argument("--set", action="append", metavar="SECTION.KEY=VALUE",
                   help="override a scene value (repeatable)")
    p.add_argument("--a0-cells", type=float, metavar="K",
                   help="elastic adhesive scenes (a0 numerical): a0 = K cells of each grid, "
                        "towards the sharp-crack limit (default: a0 fixed in metres)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")
    p.add_argument("--strict", action="store_true",
                   help="stop on plausibility warnings of the finest grid")
    p.set_defaults(func=_refine)
    p = cmd("plot", "plot a result dataset", "Plot a dataset: contact maps, fields and a "
            "profile cut (one state), a path, the curves of a sweep, or a grid refinement.")
    p.add_argument("dataset", help="netCDF result file")
    p.add_argument("-o", "--output", help="image path: .png, .pdf, .svg, ... (default: "
                   "dataset name with .png)")
    p.add_argument("--step", type=int, metavar="K",
                   help="of a load path: the state figure of step K (default: the path's "
                        "curves and the contact map of each step)")
    p.set_defaults(func=_plot)
    p = cmd("validate", "run the validation suite (make validate)",
            "Run the 2D solver against the 1D method and the references; writes "
            "validation.md and figures/ into -o (default: the current directory).")
    p.add_argument("--quick", action="store_true", help="a few points only")
    p.add_argument("-o", "--output", default=".",
                   help="output folder, created with its parents if missing (default: .)")
    p.set_defaults(func=_validate)
    p = cmd("info", "versions, FFT backend and threads",
            "Print versions, the FFT backend and thread count.")
    p.set_defaults(func=_info)
    return ap


def _close_bars() -> None:
    """Close progress bars still open (an interrupt inside a bar's constructor leaves one
    the solver could not close), so that nothing is printed after the last line."""
    mod = sys.modules.get("tqdm")
    for bar in list(getattr(getattr(mod, "tqdm", None), "_instances", ())):
        bar.close()


class Terminated(KeyboardInterrupt):
    """SIGTERM (a batch system's time limit, ``kill``) taken as Ctrl-C is: a load path keeps
    its finished steps, a sweep its finished points, a refinement its finished grids."""


#: the SIGTERMs received during the command (a command that keeps its work returns 130)
_TERMINATED: list = []


def _terminate(signum, frame):
    _TERMINATED.append(signum)
    raise Terminated(f"terminated by signal {signum}")


#: exit status after SIGTERM, as a shell reports a process ended by it (128 + 15)
SIGTERM_EXIT = 143


#: a Ctrl-C that a finalizer swallowed is raised again this much later (s), once the main
#: thread has left the finalizer (raised at once, it lands in the hook itself)
RAISE_AGAIN_DELAY = 0.05


def _raise_again(previous):
    """A ``sys.unraisablehook`` that raises again the signal whose KeyboardInterrupt a
    finalizer swallowed ("Exception ignored in __del__": a Ctrl-C that lands while numba
    compiles a kernel, on a fresh checkout's first solve, was lost and the run went on), so
    that it reaches the command where it stands; other unraisables go to ``previous``."""
    import _thread
    import signal
    import threading

    def hook(unraisable):
        exc = unraisable.exc_value
        if isinstance(exc, KeyboardInterrupt):
            sig = signal.SIGTERM if isinstance(exc, Terminated) else signal.SIGINT
            timer = threading.Timer(RAISE_AGAIN_DELAY, _thread.interrupt_main, (sig,))
            timer.daemon = True
            timer.start()
            return
        previous(unraisable)
    return hook


def main(argv=None) -> int:
    import signal
    import threading

    args = build_parser().parse_args(argv)
    args.argv = list(sys.argv[1:] if argv is None else argv)
    main_thread = threading.current_thread() is threading.main_thread()
    old = signal.signal(signal.SIGTERM, _terminate) if main_thread else None
    _TERMINATED.clear()
    unraisable, sys.unraisablehook = sys.unraisablehook, _raise_again(sys.unraisablehook)
    try:
        rc = args.func(args)
    except KeyboardInterrupt:
        _close_bars()
        print(f"spectralbem {args.command}: "
              f"{'terminated (SIGTERM)' if _TERMINATED else 'interrupted'}", file=sys.stderr)
        rc = 130
    except Exception as exc:  # a one-line reason (scene problems: one per line), non-zero exit
        print(f"spectralbem {args.command}: error: {exc}", file=sys.stderr)
        rc = 1
    finally:
        sys.unraisablehook = unraisable
        if main_thread:
            signal.signal(signal.SIGTERM, old)
    # a command that kept its finished work on SIGTERM returned 130, as on Ctrl-C
    return SIGTERM_EXIT if rc == 130 and _TERMINATED else rc


if __name__ == "__main__":
    sys.exit(main())
