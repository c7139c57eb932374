"""Every docstring example of the package runs and prints what it shows
(doctest), so that an example a reader copies is one that works."""

from __future__ import annotations

import doctest
import importlib
import pkgutil
from pathlib import Path

import pytest

import mat_hopper

PACKAGE = Path(mat_hopper.__file__).parent


def _modules_with_examples() -> list[str]:
    names = []
    for m in pkgutil.walk_packages(mat_hopper.__path__, "mat_hopper."):
        if m.name.endswith("__main__"):  # importing it runs the command line
            continue
        path = PACKAGE.joinpath(*m.name.split(".")[1:])
        source = path / "__init__.py" if m.ispkg else path.with_suffix(".py")
        if ">>> " in source.read_text(encoding="utf-8"):
            names.append(m.name)
    return sorted(names)


MODULES = _modules_with_examples()


def test_the_package_has_examples():
    assert len(MODULES) >= 6, MODULES  # the count when this test was written


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    result = doctest.testmod(importlib.import_module(name), optionflags=doctest.ELLIPSIS, verbose=False)
    assert result.attempted > 0 and result.failed == 0
