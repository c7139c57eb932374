"""Ashby classes as regions of the design space: the catalogue's class hulls.

A material class (``metal``, ``polymer``, ``natural``, ``ceramic``,
``composite``: :attr:`mat_hopper.core.materials.Material.material_class`) is the
convex hull of its catalogue members in log10 density - log10 modulus space
(the space of Ashby's charts, where classes form the familiar bubbles). A
design lies in a set of classes when every segment lies inside the hull of
at least one of them (:func:`in_classes`).

The hulls are as wide as the catalogue says, no wider: with the catalogue
of :mod:`mat_hopper.core.materials` the metals (Mg, Al, Ti, SS) span a thin
sliver along a specific modulus E/rho of 24-27 GPa cm^3/g, the polymers
(PVC, Nylon) and the ceramics (Alumina, WC) are line segments, the one
composite (CFRP) a point, and only the natural materials (three bones and
tendon) enclose an area. Wider classes need more catalogue members, not a
box: a box around two classes (the optimizer's default bounds) holds
designs no class holds (e.g. 11.9 g/cm^3 at 0.96 GPa).

The optimizer samples a class-restricted space in the hulls' bounding box
and maps each sampled point to the nearest point (log-log, Euclidean) of
the nearest allowed hull (:func:`project`): points inside stay, points
outside move to the hull's boundary, so every design it simulates lies in
the classes, degenerate hulls (segments, points) included, and the
mapping is deterministic.

Hulls of three or more non-collinear points come from
``scipy.spatial.ConvexHull`` (Qhull); segments and points, which Qhull
rejects, are kept as the ordered extreme points. Point-in-hull and
nearest-point are our own few lines (2-D, exact for these shapes), with
:data:`TOLERANCE` in log10 units so that the catalogue's own materials,
which are hull vertices, count as inside.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..core.materials import CATALOGUE, LegDesign, Material, material
from ..util.parsing import did_you_mean

TOLERANCE = 1e-9  # log10 units: on the boundary counts as inside


@dataclass(frozen=True)
class Hull:
    """A class's convex hull: vertices (k x 2, log10 g/cm^3, log10 GPa) in
    counter-clockwise order (k = 1: a point, k = 2: a segment)."""

    material_class: str
    vertices: np.ndarray
    members: tuple[str, ...]

    @property
    def kind(self) -> str:
        return {1: "point", 2: "segment"}.get(len(self.vertices), "polygon")

    def contains(self, log_rho: float, log_e: float, tol: float = TOLERANCE) -> bool:
        return self.distance(log_rho, log_e) <= tol

    def nearest(self, log_rho: float, log_e: float) -> tuple[float, float]:
        """The hull's point nearest (log10 rho, log10 E): the point itself
        when inside."""
        p = np.array([log_rho, log_e], float)
        v = self.vertices
        if len(v) >= 3 and _inside_polygon(p, v):
            return float(p[0]), float(p[1])
        if len(v) == 1:
            return float(v[0, 0]), float(v[0, 1])
        best, best_d = None, math.inf
        edges = [(v[i], v[(i + 1) % len(v)]) for i in range(len(v) if len(v) >= 3 else 1)]
        for a, b in edges:
            q = _nearest_on_segment(p, a, b)
            d = float(np.hypot(*(q - p)))
            if d < best_d:
                best, best_d = q, d
        return float(best[0]), float(best[1])

    def distance(self, log_rho: float, log_e: float) -> float:
        q = self.nearest(log_rho, log_e)
        return float(math.hypot(q[0] - log_rho, q[1] - log_e))

    def bounds(self) -> tuple[tuple[float, float], tuple[float, float]]:
        """((min, max) g/cm^3, (min, max) GPa) of the hull."""
        lo, hi = 10 ** self.vertices.min(axis=0), 10 ** self.vertices.max(axis=0)
        return (float(lo[0]), float(hi[0])), (float(lo[1]), float(hi[1]))


def _nearest_on_segment(p, a, b):
    ab = b - a
    denom = float(ab @ ab)
    t = 0.0 if denom == 0 else min(1.0, max(0.0, float((p - a) @ ab) / denom))
    return a + t * ab


def _inside_polygon(p, v) -> bool:
    """p inside the convex, counter-clockwise polygon v (edges included)."""
    for i in range(len(v)):
        a, b = v[i], v[(i + 1) % len(v)]
        cross = (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
        if cross < -TOLERANCE:
            return False
    return True


def _log_point(m: Material) -> tuple[float, float]:
    return math.log10(m.density_g_cm3), math.log10(m.modulus_gpa)


def hull_of(points, material_class: str = "custom", members: tuple[str, ...] = ()) -> Hull:
    """The convex hull of points (n x 2, log10 g/cm^3, log10 GPa)."""
    from scipy.spatial import ConvexHull, QhullError

    p = np.unique(np.asarray(points, float).reshape(-1, 2), axis=0)
    if len(p) == 0:
        raise ValueError(f"class {material_class!r} has no material with a modulus")
    if len(p) >= 3:
        try:
            h = ConvexHull(p)
            return Hull(material_class, p[h.vertices], members)  # 2-D: counter-clockwise
        except QhullError:  # collinear: a segment, handled below
            pass
    if len(p) >= 2:  # collinear (or two): the segment between the extreme points
        d = p - p[0]
        direction = d[np.argmax(np.hypot(d[:, 0], d[:, 1]))]
        t = d @ direction
        p = p[[int(np.argmin(t)), int(np.argmax(t))]]
    return Hull(material_class, p, members)


def class_hulls(catalogue=None) -> dict[str, Hull]:
    """{class: Hull} of every class of the catalogue with a modulus (the
    rigid reference MD belongs to none)."""
    mats = list((catalogue or CATALOGUE).values())
    out: dict[str, list[Material]] = {}
    for m in mats:
        if not m.rigid:
            out.setdefault(m.material_class, []).append(m)
    return {c: hull_of([_log_point(m) for m in ms], c, tuple(m.name for m in ms)) for c, ms in out.items()}


ASHBY_CLASSES = tuple(class_hulls())  # metal, polymer, natural, ceramic, composite (catalogue order)


def check_classes(classes) -> tuple[str, ...]:
    """Class names (comma-separated text or a sequence) as a tuple, each
    one of :data:`ASHBY_CLASSES`, in the order given, without repeats.

    Args:
        classes: ``"metal,polymer"``, a sequence of names, or None (no class).

    Returns:
        The names, lower case, stripped, empty ones dropped; () for None.

    Raises:
        ValueError: an unknown class (the message lists the accepted ones
            and ends with "did you mean ...?" where one is close).
    """
    if classes is None:
        return ()
    if isinstance(classes, str):
        classes = [c for c in classes.split(",")]
    out = []
    for c in classes:
        c = str(c).strip().lower()
        if not c:
            continue
        if c not in ASHBY_CLASSES:
            hint = did_you_mean(c, ASHBY_CLASSES)
            raise ValueError(
                f"unknown Ashby class {c!r}; accepted: {', '.join(ASHBY_CLASSES)}{f'; {hint}' if hint else ''}"
            )
        if c not in out:
            out.append(c)
    return tuple(out)


def hulls_for(classes) -> list[Hull]:
    hulls = class_hulls()
    return [hulls[c] for c in check_classes(classes)]


def classes_bounds(classes) -> tuple[tuple[float, float], tuple[float, float]]:
    """Bounding box ((min, max) g/cm^3, (min, max) GPa) of the classes'
    hulls: where a class-restricted search samples. A box of zero width
    (a point class) gets +-1 % so that it stays a valid log range."""
    hs = hulls_for(classes)
    if not hs:
        raise ValueError("give at least one Ashby class")
    mats = [material(n) for h in hs for n in h.members]  # exact values, not 10 ** log10
    rho = [m.density_g_cm3 for m in mats]
    e = [m.modulus_gpa for m in mats]
    (r0, r1), (e0, e1) = (min(rho), max(rho)), (min(e), max(e))
    if r0 == r1:
        r0, r1 = r0 / 1.01, r1 * 1.01
    if e0 == e1:
        e0, e1 = e0 / 1.01, e1 * 1.01
    return (float(r0), float(r1)), (float(e0), float(e1))


def project(density_g_cm3: float, modulus_gpa: float, classes) -> tuple[float, float, str]:
    """(density g/cm^3, modulus GPa, class): the point of the allowed
    classes' hulls nearest the given one in log-log space (the point itself
    when it lies in one; ties go to the first class given)."""
    hs = hulls_for(classes)
    if not hs:
        raise ValueError("give at least one Ashby class")
    p = (math.log10(density_g_cm3), math.log10(modulus_gpa))
    best = min(hs, key=lambda h: h.distance(*p))  # min keeps the first of equals
    q = best.nearest(*p)
    if best.contains(*p):
        return float(density_g_cm3), float(modulus_gpa), best.material_class
    return float(10 ** q[0]), float(10 ** q[1]), best.material_class


def segment_class(m: Material, classes=None) -> str | None:
    """The first of `classes` (default: all) whose hull holds the material,
    or None (rigid, or outside every one)."""
    if m.rigid:
        return None
    p = _log_point(m)
    for h in hulls_for(classes or ASHBY_CLASSES):
        if h.contains(*p):
            return h.material_class
    return None


def in_classes(design: LegDesign, classes=None) -> bool:
    """True when every segment of the design lies in the hull of one of
    `classes` (default: any class of the catalogue)."""
    return all(segment_class(m, classes) is not None for m in design.segments)
