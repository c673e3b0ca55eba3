"""Registries of the scene's kinds: the surfaces, materials and layers a scene file names by
``kind``.

A kind is declared once, beside the class or function it builds (:func:`register`): its scene
keys (:class:`~spectralbem.keys.Key`), how it is built from its validated section, and,
optionally, the checks that involve several of its keys or the grid.  The schema's kinds
(:data:`spectralbem.schema.KINDS`), the scene builder and the generated user guide all read
these registries, so adding a kind touches one file (docs/extending.md)::

    from spectralbem import kinds
    from spectralbem.keys import MODULUS, key

    kinds.register("material", "my_rubber",
                   {"E": key("number", "Young's modulus", "Pa", *MODULUS)},
                   build=lambda spec, context: Elastic(spec["E"], 0.5))
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

__all__ = ["Kind", "Context", "SECTIONS", "KEYS", "register", "unregister", "kind", "build",
           "check"]

#: the sections whose content depends on a ``kind``
SECTIONS = ("surface", "material", "layer")


@dataclass(frozen=True)
class Kind:
    """One kind: its scene keys, its builder ``build(spec, context)`` and an optional
    ``check(spec, grid, problems)`` of the rules that involve several keys or the grid
    (``grid``: the validated [grid] section, possibly incomplete; a key that failed its own
    check is None in ``spec``; problems are appended as ``"section.key: message"`` lines)."""

    section: str
    name: str
    keys: dict
    build: Callable
    check: Callable | None = None


@dataclass
class Context:
    """What a builder may use: the periodic cell (:class:`~spectralbem.spectral.Cell`), the
    folder relative paths start from, and the list its problems go to (a builder that
    appends a problem returns None)."""

    cell: object
    base: Path
    problems: list = field(default_factory=list)


_KINDS: dict = {s: {} for s in SECTIONS}
#: section -> kind -> {key: Key}: the schema's view (:data:`spectralbem.schema.KINDS`)
KEYS: dict = {s: {} for s in SECTIONS}


def register(section: str, name: str, keys: dict, build: Callable,
             check: Callable | None = None) -> Kind:
    """Declare (or replace) the kind ``name`` of ``section``."""
    if section not in SECTIONS:
        raise ValueError(f"section = {section!r}; allowed: {', '.join(SECTIONS)}")
    if not name.isidentifier():
        raise ValueError(f"kind name {name!r} must be an identifier (letters, digits, _)")
    if "kind" in keys:
        raise ValueError("'kind' is the selector, not a key of a kind")
    k = Kind(section, name, dict(keys), build, check)
    _KINDS[section][name] = k
    KEYS[section][name] = k.keys
    return k


def unregister(section: str, name: str) -> None:
    """Remove a kind (tests that register toy kinds clean up with it)."""
    _KINDS[section].pop(name, None)
    KEYS[section].pop(name, None)


def kind(section: str, name: str) -> Kind:
    return _KINDS[section][name]


def build(section: str, spec: dict, context: Context):
    """The object of a validated section (``spec["kind"]`` names its kind)."""
    return _KINDS[section][spec["kind"]].build(spec, context)


def check(section: str, spec: dict, grid: dict, problems: list) -> None:
    """The kind's own cross-key checks of a validated section (nothing without a check)."""
    k = _KINDS[section].get(spec.get("kind"))
    if k is not None and k.check is not None:
        k.check(spec, grid, problems)
