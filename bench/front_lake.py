"""Release rates of curved fronts under grid refinement at fixed physical a0 (docs/theory.md,
"The band is a0 wide at every orientation").

The surface h = −A (cos 2πx/L + cos 2πy/L), A = 10 µm, L = 1 mm (one smooth dimple per
cell), SLS E0 = 1 MPa, β = 10, ν = 0.5, vτ = L/64 along x, Δγ = 0.01 J/m²,
a0 = 3L/128 (3, 6, 12, 24 cells at 128² … 1024²).  At 5e4 Pa the contact surrounds one
non-contact lake (a concave front: its closing band narrows), at 6e3 Pa it is one patch
(convex: its opening band narrows).  For each N the balanced state's status, area
fraction, G1/Δγ, G2/Δγ, μ_a and CPU seconds.

Usage: python bench/front_lake.py [--sizes 128 256 512 1024] [--loads 5e4 6e3]
           [--out bench/front_lake.json]
Each finished state is written at once (a run that stops keeps the ones before it).
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from spectralbem.scenes import load_scene, solve  # noqa: E402

SIDE = 1e-3  # L (m)
AMPLITUDE = 1e-5  # A (m)
TAU = 1e-2  # s
DGAMMA = 0.01  # J/m²
OUT = Path(__file__).with_name("front_lake.json")


def heights(n: int) -> np.ndarray:
    """h = −A (cos 2πx/L + cos 2πy/L) at the n × n grid points x = iL/n, y = jL/n."""
    x = np.arange(n) / n
    c = np.cos(2 * np.pi * x)
    return -AMPLITUDE * (c[:, None] + c[None, :])


def scene(n: int, load: float, folder: Path) -> dict:
    """The scene at n² and mean pressure ``load`` (Pa), its heights written to ``folder``."""
    path = folder / f"lake_{n}.npy"
    np.save(path, heights(n))
    return {
        "scene": {"name": f"front_lake_{n}"},
        "grid": {"Lx": SIDE, "Ly": SIDE, "Nx": n, "Ny": n},
        "surface": {"kind": "file", "path": str(path)},
        "material": {"kind": "sls", "E0": 1e6, "Einf": 1e7, "tau": TAU, "nu": 0.5},
        "adhesion": {"dgamma": DGAMMA, "a0": 3 * SIDE / 128},
        "motion": {"speed": SIDE / 64 / TAU},
        "control": {"mean_pressure": float(load)},
    }


def run_one(n: int, load: float) -> dict:
    """One balanced state: its outputs and CPU seconds."""
    with tempfile.TemporaryDirectory() as tmp:
        t = time.process_time()
        ds = solve(load_scene(scene(n, load, Path(tmp)), base_dir=Path(tmp)))
        cpu = time.process_time() - t
    out = {k: float(ds[k]) for k in ("area_fraction", "mu_adhesive", "mu")}
    out.update({f"{k}_dgamma": float(ds[k]) / DGAMMA for k in ("G1", "G2")})  # G/Δγ
    out.update(N=n, load=float(load), cpu=cpu, status=str(ds["status"].values),
               iterations=int(ds["iterations"]))
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[128, 256, 512, 1024])
    ap.add_argument("--loads", type=float, nargs="+", default=[5e4, 6e3])
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    rows = json.loads(args.out.read_text()) if args.out.exists() else []
    for load in args.loads:
        for n in args.sizes:
            r = run_one(n, load)
            print(f"{load:8.0f} Pa {n:5d}²  {r['status']:>13}  area {r['area_fraction']:.4f}"
                  f"  G1 {r['G1_dgamma']:.4f}  G2 {r['G2_dgamma']:.4f} Δγ"
                  f"  μ_a {r['mu_adhesive']:.4g}  {r['cpu']:.0f} CPU-s", flush=True)
            rows = [x for x in rows if (x["N"], x["load"]) != (n, load)] + [r]
            args.out.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
