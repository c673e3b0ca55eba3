"""Kinds in registries: a kind registered in one place (here, this test file) is validated by
the schema, built by the scene and solved end to end; the built-in kinds are the registry's."""

import copy

import numpy as np
import pytest

import spectralbem as sb
from spectralbem import kinds
from spectralbem.keys import HEIGHT, MODULUS, key
from spectralbem.materials import Elastic
from spectralbem.scenes import load_scene
from spectralbem.schema import KINDS, SceneError

BASE = {
    "grid": {"Lx": 1e-3, "Ly": 1e-3, "Nx": 32, "Ny": 32},
    "surface": {"kind": "bisinusoid", "amplitude": 1e-5},
    "material": {"kind": "elastic", "E": 2e6, "nu": 0.5},
    "control": {"mean_pressure": 2e3},
}


@pytest.fixture
def toy_kinds():
    """An incompressible elastic material given by its shear modulus G (E = 3G) and a
    surface 'bump' (the bisinusoid under another name and key): declared only here."""
    kinds.register("material", "toy_rubber",
                   {"G": key("number", "shear modulus", "Pa", *MODULUS)},
                   lambda spec, context: Elastic(3.0 * spec["G"], 0.5),
                   check=lambda spec, grid, problems: problems.append(
                       "material.G: too soft for the toy") if (spec.get("G") or 1e9) < 10 else None)
    kinds.register("surface", "bump",
                   {"height": key("number", "peak-to-valley/2", "m", *HEIGHT)},
                   lambda spec, context: sb.surfaces.bisinusoid(context.cell, spec["height"]))
    yield
    kinds.unregister("material", "toy_rubber")
    kinds.unregister("surface", "bump")


def test_a_registered_kind_runs_end_to_end(toy_kinds):
    raw = copy.deepcopy(BASE)
    raw["material"] = {"kind": "toy_rubber", "G": 2e6 / 3}
    raw["surface"] = {"kind": "bump", "height": 1e-5}
    toy = sb.solve(load_scene(raw))
    ref = sb.solve(load_scene(BASE))
    assert str(toy.status.values) == str(ref.status.values) == "partial"
    # the same physical problem under other names: the same answer to round-off
    np.testing.assert_allclose(toy.pressure.values, ref.pressure.values, rtol=0,
                               atol=1e-9 * float(np.abs(ref.pressure).max()))
    assert "toy_rubber" in KINDS["material"] and "bump" in KINDS["surface"]


def test_a_registered_kind_is_validated(toy_kinds):
    raw = copy.deepcopy(BASE)
    raw["material"] = {"kind": "toy_rubber", "G": -1.0, "E": 3.0}
    with pytest.raises(SceneError) as err:
        load_scene(raw)
    text = str(err.value)
    assert "material.G: -1.0" in text and "material.E: unknown key" in text
    raw["material"] = {"kind": "toy_rubber", "G": 5.0}
    with pytest.raises(SceneError, match="material.G: too soft for the toy"):
        load_scene(raw)


def test_unregistered_kind_is_refused_naming_the_allowed_ones():
    raw = copy.deepcopy(BASE)
    raw["material"] = {"kind": "toy_rubber", "G": 1e6}
    with pytest.raises(SceneError, match="not a known material kind; allowed: elastic, sls, "
                                         "prony, tabulated"):
        load_scene(raw)


def test_register_refuses_bad_declarations():
    with pytest.raises(ValueError, match="section = 'contact'"):
        kinds.register("contact", "x", {}, lambda s, c: None)
    with pytest.raises(ValueError, match="identifier"):
        kinds.register("material", "my rubber", {}, lambda s, c: None)
    with pytest.raises(ValueError, match="selector"):
        kinds.register("material", "x", {"kind": key("string", "")}, lambda s, c: None)
