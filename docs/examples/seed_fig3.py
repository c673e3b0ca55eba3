# %% [markdown]
# # The seed's Fig. 3: contact size and eccentricity against ζ
#
# The adhesive viscoelastic sinusoid of the paper (β = 10, Γ = 0.008, p̃∞ = 0.15, k a0 =
# 0.01) by the seed's 1D method over ζ, with points of the 2D grid solver on the same
# y-invariant problem. ã = k a is the contact half-width, ẽ = k e the eccentricity (> 0:
# toward the leading edge).

# %%
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import spectralbem as sb  # noqa: E402
from spectralbem import sinusoid1d  # noqa: E402

SMALL = bool(os.environ.get("SPECTRALBEM_EXAMPLE_SMALL"))
beta, Gamma, p = 10.0, 0.008, 0.15
a0 = 0.025 if SMALL else 0.01  # k a0; the grid needs a0 ≥ one cell
cells = 512 if SMALL else 2513
zetas = np.logspace(-2, 1, 4 if SMALL else 16)
grid_zetas = [0.1] if SMALL else [0.01, 0.1, 1.0]

one_d = [sinusoid1d.solve(z, beta, Gamma, p_tilde=p, a0_tilde=a0,
                          adhesiveless_reference=False) for z in zetas]
grid = [sb.solve(sb.Scene.sinusoid(z, beta, Gamma, p_tilde=p, a0_tilde=a0,
                                   cells_per_wavelength=cells, ny=2)) for z in grid_zetas]
for z, ds in zip(grid_zetas, grid, strict=True):
    r = sinusoid1d.solve(z, beta, Gamma, p_tilde=p, a0_tilde=a0, adhesiveless_reference=False)
    print(f"ζ = {z:g}: ã grid {ds.a_tilde.item():.4f}, 1D {r.a_tilde.item():.4f}; "
          f"ẽ grid {ds.e_tilde.item():+.4f}, 1D {r.e_tilde.item():+.4f}")
    assert abs(ds.a_tilde.item() / r.a_tilde.item() - 1) < 0.01

# %%
fig, ax = plt.subplots(1, 2, figsize=(9, 3.5), constrained_layout=True)
for k, (name, label) in enumerate((("a_tilde", "ã"), ("e_tilde", "ẽ"))):
    ax[k].semilogx(zetas, [d[name].item() for d in one_d], "-", label="1D method")
    ax[k].semilogx(grid_zetas, [d[name].item() for d in grid], "o", label="2D grid")
    ax[k].set_xlabel("ζ = k v τ")
    ax[k].set_ylabel(label)
ax[0].legend()
fig.savefig("seed_fig3.png", dpi=110)
