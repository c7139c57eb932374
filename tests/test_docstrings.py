"""The public API's docstrings have Args / Returns sections (issue 19, item
5), as dm_control's do.

Public: every function of a public module (no leading underscore in its
dotted name) of the package, and every function a package re-exports in
its ``__all__`` from a private module. The command line (``mat_hopper.cli``)
is the CLI's, not the API's: its functions are documented by ``--help``.

A function with parameters (besides self/cls) needs ``Args:``; one whose
return annotation is not ``None`` needs ``Returns:`` (or ``Yields:``).
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil

import pytest

import mat_hopper

EXCLUDED_PACKAGES = ("mat_hopper.cli",)


def _modules():
    for info in pkgutil.walk_packages(mat_hopper.__path__, "mat_hopper."):
        name = info.name
        if name.startswith(EXCLUDED_PACKAGES) or name.endswith("__main__"):
            continue
        yield importlib.import_module(name)


def public_functions() -> dict[str, object]:
    """Every public function, by its dotted name (module.qualname)."""
    out = {}
    for mod in [mat_hopper, *_modules()]:
        public_module = not any(p.startswith("_") for p in mod.__name__.split("."))
        for n, v in vars(mod).items():
            if not inspect.isfunction(v) or n.startswith("_"):
                continue
            defined_here = v.__module__ == mod.__name__
            exported = n in getattr(mod, "__all__", ()) and v.__module__.startswith("mat_hopper")
            if (public_module and defined_here) or exported:
                out[f"{v.__module__}.{v.__qualname__}"] = v
    return out


def missing_sections(f) -> list[str]:
    doc = inspect.getdoc(f) or ""
    sig = inspect.signature(f)
    params = [p for p in sig.parameters if p not in ("self", "cls")]
    missing = []
    if params and "Args:" not in doc:
        missing.append("Args")
    if sig.return_annotation not in (None, "None") and "Returns:" not in doc and "Yields:" not in doc:
        missing.append("Returns")
    return missing


def test_the_check_finds_a_missing_section():
    def documented(x: int) -> int:
        """Twice x.

        Args:
            x: a number.

        Returns:
            2 x.
        """
        return 2 * x

    def bare(x: int) -> int:
        """Twice x."""
        return 2 * x

    assert missing_sections(documented) == []
    assert missing_sections(bare) == ["Args", "Returns"]


def test_public_functions_are_found():
    names = public_functions()
    assert "mat_hopper.core.sim.simulate" in names and "mat_hopper.core.materials.paper_designs" in names
    assert not any(n.startswith("mat_hopper.cli") for n in names)


@pytest.mark.parametrize("name", sorted(public_functions()))
def test_public_docstring_has_args_and_returns(name):
    assert missing_sections(public_functions()[name]) == [], name
