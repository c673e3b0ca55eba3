"""Quantities with units on input: "2 MPa", "62.5 um", "4 mm/s" read by pint and converted to
the SI unit a scene key (or a file attribute) is stated in."""

from __future__ import annotations

import functools

#: schema units that accept a quantity with a unit ("2 MPa"): their pint spelling
PINT_UNITS = {"m": "m", "Pa": "Pa", "s": "s", "m/s": "m/s", "J/m²": "J/m**2",
              "deg": "degree"}


@functools.lru_cache(maxsize=1)
def _registry():
    import pint

    return pint.UnitRegistry()


def quantity(text: str, units: str):
    """The number of ``units`` (the schema's SI unit) in the quantity ``text`` ("2 MPa",
    "10 um", "4 mm/s"), parsed by pint; or a message (str) saying why it cannot be."""
    from .schema import short  # the package's shortened quoting of values in messages

    if units not in PINT_UNITS:
        return (f"{short(text)} carries a unit; this key takes a plain number"
                + (f" in {units}" if units and units != "1" else ""))
    try:
        import pint
    except ImportError:  # pragma: no cover - pint is a dependency
        return f"{short(text)} carries a unit; give a plain number in {units} (pint is missing)"
    try:
        q = _registry().Quantity(text)
    except Exception as exc:  # noqa: BLE001 - pint's parser raises many kinds
        return f"{short(text)}: not a quantity pint can read ({type(exc).__name__})"
    try:
        return float(q.to(PINT_UNITS[units]).magnitude)
    except pint.DimensionalityError:
        return (f"{short(text)} is not a quantity in {units} (its dimension is "
                f"{q.dimensionality}); give it in {units} or a compatible unit")

