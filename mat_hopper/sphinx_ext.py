"""A Sphinx extension for the book: runtime per chapter at both profiles
(and one fix of the HTML, :func:`_unique_scripts`).

myst-nb's ``nb-exec-table`` shows how long each notebook of *this* build
took to execute. A reader also wants the other profile's cost (what does
``make book`` cost, when CI only builds the quick book?), which no build
measures at once. So this extension

- records, once every notebook of a build has executed (Sphinx's
  ``env-updated``), each chapter's execution time as myst-nb measured it
  into ``results/<profile>/runtimes.csv`` (the profile from
  ``$MAT_HOPPER_PROFILE``), and
- renders the ``runtime-table`` directive as a table with one row per
  chapter and one column per profile: this build's times, measured now,
  and the other profile's from the record of its last build in the same
  folder (with the date of that build); where that profile has not been
  built there, from the reference record committed with the book
  (``book/runtimes/<profile>.csv``: a build from a fresh clone, with its
  date and machine), or "–" where there is none.

The times are myst-nb's own measurement (``exec_data["runtime"]``), not
ours; we keep only the record across builds, which myst-nb does not.
"""

from __future__ import annotations

import datetime as _dt
import posixpath
from pathlib import Path

import pandas as pd
from docutils import nodes
from sphinx.addnodes import pending_xref
from sphinx.transforms.post_transforms import SphinxPostTransform
from sphinx.util.docutils import SphinxDirective

from .experiments.profiles import PROFILES, resolve_profile

RUNTIME_CSV = "runtimes.csv"
REFERENCE_DIR = ("book", "runtimes")  # committed reference records, <profile>.csv
_KEY = "mat_hopper_runtime_table"


def runtime_record(exec_data: dict[str, dict], titles: dict[str, str] | None = None) -> pd.DataFrame:
    """The runtimes of one build as a table: one row per executed document
    (docname, title, runtime_s, succeeded), in document order, from
    myst-nb's per-document ``exec_data``; documents without a runtime are
    left out.

    Args:
        exec_data: {docname: myst-nb's exec_data dict (``runtime``, s, and
            ``succeeded``), or None}.
        titles: {docname: title}; None (the default) or a missing docname:
            the title is the docname.

    Returns:
        A pandas DataFrame with columns ``docname``, ``title``,
        ``runtime_s`` (float, s) and ``succeeded`` (bool; False where
        exec_data has no ``succeeded``), one row per document with a runtime,
        sorted by docname; empty (with these columns) when none has one.
    """
    titles = titles or {}
    rows = []
    for doc in sorted(exec_data):
        data = exec_data[doc] or {}
        rt = data.get("runtime")
        if rt is None:
            continue
        rows.append(
            {
                "docname": doc,
                "title": titles.get(doc, doc),
                "runtime_s": float(rt),
                "succeeded": bool(data.get("succeeded", False)),
            }
        )
    return pd.DataFrame(rows, columns=["docname", "title", "runtime_s", "succeeded"])


def runtime_table(records: dict[str, pd.DataFrame | None]) -> pd.DataFrame:
    """Chapters as rows, profiles as columns (``<profile>_s``, seconds; nan
    where that profile has no record of the chapter), from each profile's
    :func:`runtime_record`, and a last row ``total``. Columns: docname,
    title, then one per profile in :data:`PROFILES` order.

    Args:
        records: {profile name: its :func:`runtime_record` table, or None
            where it has none}; None and empty tables count as no record, and
            names not in :data:`PROFILES` are ignored.

    Returns:
        A pandas DataFrame: one row per docname found in any record (sorted
        by docname, the title from the first record naming it), then the
        ``total`` row (docname ``""``), whose ``<profile>_s`` is the sum of
        the chapters' known times (s), or nan when there is none.
    """
    frames = {p: r for p, r in records.items() if r is not None and len(r)}
    docs: dict[str, str] = {}
    for r in frames.values():
        for d, t in zip(r["docname"], r["title"]):
            docs.setdefault(d, t)
    order = sorted(docs)
    out = pd.DataFrame({"docname": order, "title": [docs[d] for d in order]})
    for p in PROFILES:
        r = frames.get(p)
        col = f"{p}_s"
        out[col] = float("nan") if r is None else out["docname"].map(r.set_index("docname")["runtime_s"]).astype(float)
    total = {"docname": "", "title": "total"}
    for p in PROFILES:
        col = f"{p}_s"
        total[col] = float(out[col].sum()) if out[col].notna().any() else float("nan")
    return pd.concat([out, pd.DataFrame([total])], ignore_index=True)


def _record_path(srcdir, profile: str) -> Path:
    return Path(srcdir) / "results" / profile / RUNTIME_CSV


def _reference_path(srcdir, profile: str) -> Path:
    return Path(srcdir).joinpath(*REFERENCE_DIR, f"{profile}.csv")


def _other_profile(srcdir, profile: str) -> tuple[pd.DataFrame | None, str]:
    """The record of another profile's build and its label for the table
    header: this folder's last build, else the committed reference build,
    else none."""
    for path, where in ((_record_path(srcdir, profile), "last built here"), (_reference_path(srcdir, profile), "")):
        if not path.is_file():
            continue
        r = pd.read_csv(path)
        when = str(r["built_at"].iloc[0]) if "built_at" in r and len(r) else ""
        if where:
            return r, f"{where} {when}".strip()
        machine = str(r["machine"].iloc[0]) if "machine" in r and len(r) else "another machine"
        return r, f"reference build {when}, {machine}".strip()
    return None, "not built in this folder yet"


def _exec_data(env) -> dict[str, dict]:
    from myst_nb.sphinx_ import NbMetadataCollector

    return {d: v.get("exec_data") for d, v in NbMetadataCollector.get_doc_data(env).items() if v.get("exec_data")}


def _titles(env) -> dict[str, str]:
    return {d: t.astext() for d, t in env.titles.items()}


def _record(app, env):
    """env-updated: write this build's runtimes (when any notebook ran)."""
    from .util.atomic import write_csv

    rec = runtime_record(_exec_data(env), _titles(env))
    if len(rec):
        profile = resolve_profile(None).name
        path = _record_path(app.srcdir, profile)
        path.parent.mkdir(parents=True, exist_ok=True)
        write_csv(rec.assign(built_at=_dt.datetime.now().isoformat(timespec="minutes")), path)
    from myst_nb.sphinx_ import NbMetadataCollector

    return [d for d, v in NbMetadataCollector.get_doc_data(env).items() if v.get(_KEY)]


class RuntimeTableNode(nodes.General, nodes.Element):
    pass


class RuntimeTableDirective(SphinxDirective):
    has_content = False

    def run(self):
        from myst_nb.sphinx_ import NbMetadataCollector

        NbMetadataCollector.set_doc_data(self.env, self.env.docname, _KEY, True)
        return [RuntimeTableNode()]


class RuntimeTablePostTransform(SphinxPostTransform):
    default_priority = 8  # before the reference resolvers, as myst-nb's nb-exec-table

    def run(self, **kwargs):
        for node in list(self.document.findall(RuntimeTableNode)):
            node.replace_self(self._table())

    def _table(self):
        env = self.env
        this = resolve_profile(None).name
        records, dates = {}, {}
        for p in PROFILES:
            if p == this:
                records[p] = runtime_record(_exec_data(env), _titles(env))
                dates[p] = "this build"
                continue
            records[p], dates[p] = _other_profile(env.srcdir, p)
        t = runtime_table(records)
        cols = list(PROFILES)
        table = nodes.table(classes=["colwidths-auto"])
        tgroup = nodes.tgroup(cols=1 + len(cols))
        table += tgroup
        for _ in range(1 + len(cols)):
            tgroup += nodes.colspec(colwidth=1)
        thead, tbody = nodes.thead(), nodes.tbody()
        tgroup += thead
        tgroup += tbody
        head = nodes.row()
        head += nodes.entry("", nodes.paragraph(text="chapter"))
        for p in cols:
            head += nodes.entry("", nodes.paragraph(text=f"{p} profile (s), {dates[p]}"))
        thead += head
        here = env.docname
        for row in t.itertuples(index=False):
            r = nodes.row()
            para = nodes.paragraph()
            if row.docname:
                ref = pending_xref(
                    refdoc=here,
                    reftarget=posixpath.relpath(row.docname, posixpath.dirname(here)),
                    reftype="doc",
                    refdomain="std",
                    refexplicit=True,
                    refwarn=True,
                )
                ref += nodes.inline(text=row.title)
                para += ref
            else:
                para += nodes.strong(text=row.title)
            r += nodes.entry("", para)
            for p in cols:
                v = getattr(row, f"{p}_s")
                text = "–" if pd.isna(v) else f"{v:.0f}"
                missing = int(t[f"{p}_s"].iloc[:-1].isna().sum())
                if not row.docname and missing and not pd.isna(v):
                    text += f" (without the {missing} chapter{'s' if missing > 1 else ''} marked –)"
                r += nodes.entry("", nodes.paragraph(text=text))
            tbody += r
        return table


def _unique_scripts(app, pagename, templatename, context, doctree):
    """html-page-context: drop repeated script tags. Jupyter Book 1 sets up
    sphinx-thebe so that its configuration script (``const THEBE_JS_URL =
    ...``) lands on every page twice, and a browser then reports a
    SyntaxError for the second ``const``."""
    scripts = context.get("script_files")
    if not scripts:
        return
    seen, unique = set(), []
    for js in scripts:
        # an inline script comes with filename None or "" (the same body added twice)
        name = getattr(js, "filename", str(js)) or ""
        key = (name, tuple(sorted((k, str(v)) for k, v in getattr(js, "attributes", {}).items())))
        if key not in seen:
            seen.add(key)
            unique.append(js)
    scripts[:] = unique


def setup(app):
    """Register the extension with Sphinx (``extensions`` in the book's
    configuration): the ``runtime-table`` directive and its post-transform,
    the recording of this build's runtimes on ``env-updated``, and the
    removal of repeated script tags on ``html-page-context``.

    Args:
        app: the Sphinx application.

    Returns:
        The extension's metadata: ``{"parallel_read_safe": True,
        "parallel_write_safe": True}``.
    """
    app.connect("html-page-context", _unique_scripts)
    app.add_node(RuntimeTableNode)
    app.add_directive("runtime-table", RuntimeTableDirective)
    app.add_post_transform(RuntimeTablePostTransform)
    app.connect("env-updated", _record)
    return {"parallel_read_safe": True, "parallel_write_safe": True}


__all__ = ["RUNTIME_CSV", "runtime_record", "runtime_table", "setup"]
