"""Results: what a solved state reports, and its Dataset.

The grid's states (:class:`spectralbem.state.ContactState`, :class:`AdhesiveState`) become
xarray Datasets here, every variable named and described by io's variable table
(:data:`spectralbem.io.SCALARS`, :data:`spectralbem.io.FIELDS`); seed scenes on the grid
report the 1D method's dimensionless names (:data:`spectralbem.oned.SCALARS`), with the
edges and release rates of a y-invariant state (:func:`seed_front_outputs`).
"""

from __future__ import annotations

import math

import numpy as np

from .io import FIELDS, SCALARS, STATUS
from .io import attrs as _attrs
from .keys import LOAD_TOL
from .observables import ProfileSlope, field_of

__all__ = ["grid_dataset", "seed_dataset", "seed_front_outputs", "edges_y_invariant",
           "quotient", "friction_observables", "front_friction", "profile_friction"]


def quotient(num: float, den: float, num_scale: float = 0.0, den_scale: float = 0.0,
             den_tol: float = 1e-9) -> float:
    """num/den with the 1D method's convention at no load (oned.branches._quotient): 0/0 = 0 (no
    force at no load), ±inf for a finite numerator over 0.  A value within 1e-9 of its scale
    (the sum of the magnitudes it came from) counts as 0: round-off of a vanishing sum; the
    denominator within ``den_tol`` of its scale (a load known to a tolerance: keys.LOAD_TOL
    for the load an adhesive front carries)."""
    if abs(den) > den_tol * den_scale and den != 0.0:
        return num / den
    return 0.0 if abs(num) <= 1e-9 * num_scale else math.copysign(math.inf, num)


def friction_observables(op, heights) -> dict:
    """The observables whose sums Σ p f an adhesive solve records for each band state
    (``observables`` of adhesive.solve_adhesive, :mod:`spectralbem.observables`): the unit
    field (``load``, the scalar 1) and the rigid profile's slopes −v̂·∇h (``force``) and
    −v̂⊥·∇h (``lateral``), v̂⊥ = ẑ × v̂, formed when a sum needs them."""
    from .friction import sliding_direction

    vhat = sliding_direction(op)
    vperp = (-vhat[1], vhat[0])
    return {"load": 1.0, "force": ProfileSlope(op.cell, heights, vhat),
            "lateral": ProfileSlope(op.cell, heights, vperp)}


def front_friction(r, obs: dict) -> dict:
    """Friction (``force``) and lateral coefficients of a partial adhesive state ``r`` at its
    balanced sub-cell front: the force on the rigid profile, Σ p f with the fields of
    :func:`friction_observables`, interpolated between the mask's state and its band states
    like every integrated quantity (front.at_front), over the load likewise (Eq. (19) in 2D:
    on the contact −v̂·∇u = −v̂·∇h; the profile's slope is smooth where u's spectral
    derivative at the mask edge is not)."""
    from . import front

    p = r.pressure
    sums, scale = _sums(p, obs)
    at_front = front.at_front(r.tests, r.offset_out, sums, r.a0)
    # the front carries its load to LOAD_TOL: a smaller one is no net normal force (the rough
    # path at 0 Pa read μ = +inf, −inf or 6e5 by the sign and size of a 1e-9-1e-6 Pa residual)
    return _friction_quotients(at_front, scale, LOAD_TOL)


def profile_friction(p, obs: dict) -> dict:
    """:func:`front_friction` of the pressure ``p`` on its own mask (no front to move)."""
    return _friction_quotients(*_sums(p, obs))


def _sums(p, obs):
    """Σ p f and Σ |p f| of each observable (each field formed once)."""
    sums, scale = {}, {}
    for k, f in obs.items():
        pf = p * field_of(f)
        sums[k], scale[k] = float(np.sum(pf)), float(np.sum(np.abs(pf)))
    return sums, scale


def _friction_quotients(sums, scale, den_tol: float = 1e-9) -> dict:
    return {k: quotient(sums[k], sums["load"], scale[k], scale["load"], den_tol)
            for k in ("force", "lateral")}


def edges_y_invariant(mask, offset, cell):
    """The distances (l1, l2) of the −x and +x edges from the summit (trailing and leading
    when v̂·x̂ ≥ 0), averaged over rows, with the sub-cell offsets of the outer front
    cells."""
    lam = cell.Lx
    x = (cell.x + lam / 2) % lam - lam / 2
    l1s, l2s = [], []
    for j in range(cell.Ny):
        row = mask[:, j]
        if not row.any() or row.all():
            return np.nan, np.nan
        xs = x[row]
        i_lo = int(np.flatnonzero(row & (x == xs.min()))[0])
        i_hi = int(np.flatnonzero(row & (x == xs.max()))[0])
        s_lo = offset[(i_lo - 1) % cell.Nx, j]
        s_hi = offset[(i_hi + 1) % cell.Nx, j]
        l1s.append(-(xs.min() - cell.hx / 2) + (s_lo if np.isfinite(s_lo) else 0.0))
        l2s.append(xs.max() + cell.hx / 2 + (s_hi if np.isfinite(s_hi) else 0.0))
    return float(np.mean(l1s)), float(np.mean(l2s))


SEED_EXTRA = {
    "mu_bar_mask": "μ/Λ̃ from the rigid-profile force on the cell mask",
    "mu_bar_dissipation": "μ/Λ̃ from the spectral dissipation",
    "mu_bar_lateral": "lateral force over normal force, over Λ̃",
}



def grid_dataset(cell, scalars: dict, status: str, fields: dict):
    """A physical grid state as a Dataset: the ``scalars`` (names of io.SCALARS), its
    ``status`` and the 2D ``fields`` (names of io.FIELDS) on x, y in m."""
    import xarray as xr

    data = {k: ((), float(v), _attrs(SCALARS[k])) for k, v in scalars.items()}
    data["status"] = ((), status, _attrs(STATUS))
    for k, v in fields.items():
        data[k] = (("x", "y"), v, _attrs(FIELDS[k]))
    return xr.Dataset(data, coords={
        "x": ("x", cell.x, {"units": "m", "long_name": "position along x"}),
        "y": ("y", cell.y, {"units": "m", "long_name": "position along y"})})


def seed_dataset(cell, scalars: dict, status: str, pressure_tilde, contact, G_front=None):
    """A seed scene's grid state as a Dataset in the 1D method's names (k x, k y, p/p*)."""
    import xarray as xr

    from .oned import SCALARS as names

    names = {**names, **SEED_EXTRA}
    data = {k: ((), float(v), {"units": "1", "long_name": names.get(k, k)})
            for k, v in scalars.items()}
    data["status"] = ((), status, {"long_name": "partial | full_contact | detached | "
                                                "not_converged", "units": "1"})
    data["pressure_tilde"] = (("x", "y"), pressure_tilde, {"long_name": "p/p*", "units": "1"})
    data["contact"] = (("x", "y"), contact.astype(np.int8), {"long_name": "contact mask",
                                                             "units": "1"})
    if G_front is not None:
        data["G_front"] = (("x", "y"), G_front, _attrs(FIELDS["G_front"]))
    return xr.Dataset(data, coords={"x": ("x", cell.x, {"units": "1", "long_name": "k x"}),
                                    "y": ("y", cell.y, {"units": "1", "long_name": "k y"})})


def seed_front_outputs(op, r, dgamma, obs: dict) -> tuple:
    """(l1, l2, scalars) of a partial y-invariant adhesive state ``r`` of the seed scene:
    the edges from the summit with their sub-cell offsets, G1/Δγ and G2/Δγ at the balanced
    edges, and the friction μ/Λ̃ (force, lateral) of the sub-cell front from the observables
    ``obs`` (:func:`friction_observables`)."""
    cell, a0e = op.cell, r.a0
    l1, l2 = edges_y_invariant(r.contact, r.offset_out, cell)
    G = []
    for ci in sorted(r.tests.closing):
        close, open_ = r.tests.closing[ci], r.tests.opening[ci]
        col = r.tests.colour_map[ci]
        sel = col & np.isfinite(r.offset_out)  # no balanced edge: s, G undefined
        s = float(r.offset_out[sel].mean()) if sel.any() else np.nan
        Gc, Go = close.dU / close.area, open_.dU / open_.area
        # G at the balanced edge: the closing (opening) band's value stands at its start x_b
        # (x_b − a0) in the seed's definition, at its midpoint when the edge is the
        # sharp-crack one (shift a0/2, elastic scenes)
        G.append(Go + (Gc - Go) * (a0e + s - r.edge_shift) / a0e)
    if not op.viscoelastic:
        # δL_P ≡ 0: the balanced edge releases Δγ exactly (front.front_outputs), where the
        # band means interpolated linearly to the sharp-crack edge miss it by O(a0²)
        # (G1/Δγ = 1.049 at a0 = 16 cells of 1024 per wavelength)
        G = [float(np.mean(dgamma))] * len(G)
    # integrated quantities at the sub-cell front (first order in offset/a0)
    out = {f"mu_bar_{k}_front": v for k, v in front_friction(r, obs).items()}
    if r.crack_tips is not None and not r.crack_tips.any():
        G = [0.0]  # every edge held by contact (Γ → 0): no crack tip (front.py)
    if len(G) == 1:
        G = G * 2
    # colour 0 is trailing (v̂·n < 0); for elastic scenes one colour for both edges
    out.update(G1_over_dgamma=G[0] / dgamma, G2_over_dgamma=G[1] / dgamma)
    return l1, l2, out
