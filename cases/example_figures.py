"""One small example of each kind of figure `spectralbem plot` draws, in docs/figures/.

Run by ``make figures`` (about a minute on 2 cores); each figure is what
``spectralbem plot result.nc`` draws for that kind of dataset:

* example_state_rough.png — a viscoelastic rough state (cases/rubber_rough.toml at 128²);
* example_state_adhesive.png — an adhesive state with its front coloured by G/Δγ
  (cases/jkr_sphere.toml, 256², zero load);
* example_state_rough_adhesive.png — an adhesive viscoelastic rough state: the front's
  crack tips coloured by G/Δγ, the edges held by contact in black
  (cases/rough_convergence.toml, 256², loading at 1e4 Pa);
* example_path.png — a load/unload path with adhesion hysteresis
  (cases/rough_convergence.toml at 128², loads 1e4, 3e4, 1e4, 3e3 Pa);
* example_sweep.png — μ and the contact area against the sliding speed
  (cases/rubber_rough.toml at 64², 9 speeds, the local dask cluster);
* example_profile_1d.png — the seed's 1D method (cases/seed_sinusoid_1d.toml);
* example_refinement.png — a grid refinement, `spectralbem refine` (cases/rubber_rough.toml
  at 64², 128², 256², 512²).

Usage: python cases/example_figures.py [--only state_rough path ...]
"""

from __future__ import annotations

import argparse
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spectralbem as sb  # noqa: E402
from spectralbem.plotting import plot_dataset  # noqa: E402
from spectralbem.scenes import load_scene  # noqa: E402

CASES = Path(__file__).resolve().parent
OUT = CASES.parent / "docs" / "figures"


def _scene(name: str, **overrides):
    return load_scene(CASES / f"{name}.toml", overrides=overrides)


def _sweep():
    from spectralbem.sweep import run_sweep

    with tempfile.TemporaryDirectory() as tmp:
        path = run_sweep(CASES / "rubber_rough.toml", [("motion.speed", np.logspace(-5, 0, 9))],
                         Path(tmp) / "sweep.nc", overrides={"grid.Nx": 64, "grid.Ny": 64},
                         workers=2, progress=False)
        import xarray as xr

        with xr.open_dataset(path) as ds:
            return ds.load()


def _refinement():
    from spectralbem.refinement import refine

    with tempfile.TemporaryDirectory() as tmp:
        return refine(CASES / "rubber_rough.toml", [64, 128, 256, 512], Path(tmp) / "r.nc")


FIGURES = {
    "state_rough": lambda: sb.solve(_scene("rubber_rough", **{"grid.Nx": 128,
                                                              "grid.Ny": 128})),
    "state_adhesive": lambda: sb.solve(_scene("jkr_sphere", **{"control.mean_pressure": 0.0})),
    "state_rough_adhesive": lambda: sb.solve(_scene("rough_convergence", **{
        "control.mean_pressure": 1e4})),
    "path": lambda: sb.solve(_scene("rough_convergence", **{
        "grid.Nx": 128, "grid.Ny": 128, "control.mean_pressure": [1e4, 3e4, 1e4, 3e3]})),
    "sweep": _sweep,
    "profile_1d": lambda: sb.solve(_scene("seed_sinusoid_1d")),
    "refinement": _refinement,
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="+", choices=sorted(FIGURES), default=sorted(FIGURES))
    args = ap.parse_args(argv)
    for name in args.only:
        ds = FIGURES[name]()
        path = OUT / f"example_{name}.png"
        fig = plot_dataset(ds, path)
        plt.close(fig)
        print(f"{path.relative_to(CASES.parent)}", flush=True)


if __name__ == "__main__":
    main()
