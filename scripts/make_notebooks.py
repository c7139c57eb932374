#!/usr/bin/env python3
"""Write the book's notebooks from their sources, clean.

Each chapter's source is ``notebooks/src/<name>.py`` in the "percent"
format: ``# %%`` starts a code cell, ``# %% [markdown]`` a markdown cell
(each line's leading ``# `` removed), optional cell tags as
``# %% tags=["hide-input"]``; text before the first marker is the file's
own comment and is dropped. The notebook ``notebooks/<name>.ipynb`` is
written without outputs or execution counts, with deterministic cell ids
and the ``python3`` kernel (the interpreter that runs Jupyter: .venv's).

    python scripts/make_notebooks.py          # (re)write every notebook
    python scripts/make_notebooks.py --check  # exit 1 if any is stale or dirty

Edit the sources, not the .ipynb files (tests/test_book.py checks that
they agree).
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

import nbformat

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / "notebooks" / "src"
OUT = ROOT / "notebooks"
MARKER = re.compile(r"^# %%(?P<md> \[markdown\])?(?P<opts>.*)$")
KERNELSPEC = {"name": "python3", "display_name": "Python 3 (ipykernel)", "language": "python"}


def _options(text: str) -> dict:
    text = text.strip()
    if not text:
        return {}
    m = re.fullmatch(r"tags=(\[.*\])", text)
    if not m:
        raise ValueError(f"cell marker options must be tags=[...], got {text!r}")
    return {"tags": json.loads(m.group(1))}


def parse(source: str) -> list[dict]:
    """Cells of a percent-format source: dicts with type, text, metadata."""
    cells, cur = [], None
    for line in source.splitlines():
        m = MARKER.match(line)
        if m:
            cur = {"type": "markdown" if m.group("md") else "code", "lines": [], "meta": _options(m.group("opts"))}
            cells.append(cur)
        elif cur is not None:
            if cur["type"] == "markdown":
                if line.strip() and not line.startswith("#"):
                    raise ValueError(f"markdown line does not start with '#': {line!r}")
                line = line[2:] if line.startswith("# ") else line[1:]
            cur["lines"].append(line)
    out = []
    for c in cells:
        lines = c["lines"]
        while lines and not lines[-1].strip():
            lines.pop()
        while lines and not lines[0].strip():
            lines.pop(0)
        if lines:
            out.append({"type": c["type"], "text": "\n".join(lines), "metadata": c["meta"]})
    return out


def build(src: Path) -> nbformat.NotebookNode:
    nb = nbformat.v4.new_notebook()
    nb.metadata = {"kernelspec": dict(KERNELSPEC), "language_info": {"name": "python"}}
    for i, c in enumerate(parse(src.read_text(encoding="utf-8"))):
        make = nbformat.v4.new_markdown_cell if c["type"] == "markdown" else nbformat.v4.new_code_cell
        cell = make(c["text"], metadata=c["metadata"])
        cell.id = f"{src.stem}-{i:02d}"
        nb.cells.append(cell)
    nbformat.validate(nb)
    return nb


def render(nb) -> str:
    return nbformat.writes(nb) + "\n"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--check", action="store_true", help="only check that every notebook is up to date and clean")
    args = p.parse_args(argv)
    sources = sorted(SRC.glob("*.py"))
    if not sources:
        print(f"no sources in {SRC}", file=sys.stderr)
        return 1
    stale = []
    for src in sources:
        target = OUT / f"{src.stem}.ipynb"
        text = render(build(src))
        if args.check:
            if not target.exists() or target.read_text(encoding="utf-8") != text:
                stale.append(target.name)
        elif not target.exists() or target.read_text(encoding="utf-8") != text:
            target.write_text(text, encoding="utf-8")
            print(f"wrote {target.relative_to(ROOT)}")
    orphans = sorted({p.stem for p in OUT.glob("*.ipynb")} - {s.stem for s in sources})
    if orphans:
        print(f"notebooks without a source: {', '.join(orphans)}", file=sys.stderr)
        return 1
    if stale:
        print(f"stale or dirty notebooks (run python scripts/make_notebooks.py): {', '.join(stale)}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
