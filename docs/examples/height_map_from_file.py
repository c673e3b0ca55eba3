# %% [markdown]
# # A measured height map from a file
#
# Height maps are read from `.npy`, text/CSV matrices (rows along x), netCDF (a variable on
# dimensions (x, y); uniformly spaced coordinates give the physical size, checked against
# the grid) or, with the optional SurfaceTopography package, instrument formats. Values are
# multiplied by `surface.scale` (metres per file unit). Here a "measurement" in µm is made
# from a synthetic surface and saved as CSV, then read back as a scene.

# %%
import os
import tempfile

import numpy as np

import spectralbem as sb
from spectralbem.scenes import load_scene
from spectralbem.spectral import Cell
from spectralbem.surfaces import self_affine

SMALL = bool(os.environ.get("SPECTRALBEM_EXAMPLE_SMALL"))
N, L = (32, 1e-3) if SMALL else (256, 1e-3)

cell = Cell(L, L, N, N)
h = self_affine(cell, 0.8, rolloff=2 * np.pi / 2.5e-4, cutoff=2 * np.pi / (L / 8 if SMALL
                else 6.25e-5), rms_slope=0.1, seed=7)
folder = tempfile.mkdtemp()
path = os.path.join(folder, "topography_um.csv")
np.savetxt(path, h * 1e6, delimiter=",")  # the "instrument" writes micrometres
print(f"rms height {h.std() * 1e6:.3f} µm, written to {path}")

# %%
scene = {
    "grid": {"Lx": "1 mm", "Ly": "1 mm", "Nx": N, "Ny": N},
    "surface": {"kind": "file", "path": path, "scale": 1e-6},  # µm -> m
    "material": {"kind": "elastic", "E": "1 MPa", "nu": 0.5},
    "control": {"mean_pressure": "10 kPa"},
}
ds = sb.solve(load_scene(scene))
print(f"{ds.status.item()}: contact area {float(ds.area_fraction):.4f}, "
      f"penetration {float(ds.penetration) * 1e6:.3f} µm")
assert ds.status.item() == "partial"
assert np.allclose(ds.heights.values, h, atol=1e-12 * abs(h).max() + 1e-15)
