"""How stiff the foot's contact with the terrain is: one named setting,
``SimSettings.contact``.

MuJoCo's contacts are soft: each is a constraint whose reference
acceleration is that of a damped spring, set by ``solref = (timeconst,
dampratio)`` (MuJoCo documentation, "Computation", "Solver parameters").
The time constant sets how far the foot sinks and how quickly it is pushed
back out; the impedance ``solimp`` is left at MuJoCo's default.

``authors``
    MuJoCo's default soft contact, ``solref = (0.02, 1)``: the authors'
    file sets no solver parameters. Default.
``stiff``
    a time constant of 1 ms, critically damped: ``solref = (0.001, 1)``.
``stiff-elliptic``
    ``stiff`` with MuJoCo's elliptic friction cones in place of the
    pyramidal ones the model otherwise uses (MuJoCo documentation,
    "Computation", "Contact": a pyramidal cone couples the normal and
    friction forces through its edges; the elliptic cone is the
    Coulomb cone itself). A stiff leg that bends rings at lift-off, and
    the pyramid's coupling turns the ringing's tangential acceleration into
    normal pushes that re-engage the foot; the elliptic cone does so less,
    and such a leg comes closer to its rigid twin as it stiffens
    (``book/records/README.md``).

:func:`mat_hopper.core.mjcf.build_spec` sets the named ``solref`` on every
geom that can touch (the foot and the terrain), so MuJoCo's mix of the two
geoms' parameters (a solmix-weighted mean) is exactly the named pair.

A time constant is honoured only down to twice the physics step: MuJoCo's
documentation (XML reference, option/flag ``refsafe``, on by default):
"If this setting is enabled, the solver uses max(solref[0], 2*timestep) in
place of solref[0] separately for each active constraint" (and its
"Solver parameters" section asks for a time constant of at least two
steps). :func:`contact_max_timestep` is that limit, which ``--timestep
auto`` honours (:func:`mat_hopper.core.stable_step.auto_substeps`); a step
given by number above it runs with MuJoCo's raised time constant.
"""

from __future__ import annotations

from ..util.parsing import parse_name

__all__ = [
    "CONTACTS",
    "DEFAULT_CONTACT",
    "ELLIPTIC_CONTACTS",
    "check_contact",
    "contact_max_timestep",
    "contact_solref",
    "elliptic_cone",
]

# Contact name -> MuJoCo solref (timeconst s, dampratio), the one table.
# "authors" is MuJoCo's default (mjs_defaultGeom: solref 0.02 1), exactly.
CONTACTS = {
    "authors": (0.02, 1.0),
    "stiff": (0.001, 1.0),
    "stiff-elliptic": (0.001, 1.0),
}
# The contacts whose friction cone is elliptic (the rest: pyramidal).
ELLIPTIC_CONTACTS = ("stiff-elliptic",)
DEFAULT_CONTACT = "authors"
# MuJoCo uses max(solref[0], 2*timestep) as the time constant (XML reference,
# option/flag refsafe, on by default): a time constant holds for steps up to half of it.
TIMECONST_PER_TIMESTEP = 2.0


def check_contact(contact) -> str:
    """The contact setting named (case-insensitive, blanks trimmed;
    :func:`mat_hopper.util.parsing.parse_name`), as spelled in :data:`CONTACTS`.

    Args:
        contact: ``"authors"`` or ``"stiff"``, any case.

    Returns:
        The name as spelled in :data:`CONTACTS` (``"Stiff"`` gives ``"stiff"``).

    Raises:
        ValueError: an empty name or one not in :data:`CONTACTS` (the
            message lists them).
    """
    return parse_name(contact, CONTACTS, "contact")


def contact_solref(contact) -> tuple[float, float]:
    """MuJoCo's ``solref`` of a contact setting.

    Args:
        contact: a name of :data:`CONTACTS`, any case.

    Returns:
        (timeconst s, dampratio): (0.02, 1.0) for ``authors``, (0.001, 1.0)
        for ``stiff``.

    Raises:
        ValueError: an unknown name (:func:`check_contact`).
    """
    return CONTACTS[check_contact(contact)]


def elliptic_cone(contact) -> bool:
    """Whether a contact setting uses MuJoCo's elliptic friction cones
    (otherwise the pyramidal ones, the model's default).

    Args:
        contact: a name of :data:`CONTACTS`, any case.

    Returns:
        True for the names in :data:`ELLIPTIC_CONTACTS` (``stiff-elliptic``).

    Raises:
        ValueError: an unknown name (:func:`check_contact`).
    """
    return check_contact(contact) in ELLIPTIC_CONTACTS


def contact_max_timestep(contact) -> float:
    """The largest physics step (s) at which MuJoCo honours the contact's
    time constant: timeconst / 2 (MuJoCo's guidance, module doc).

    Args:
        contact: a name of :data:`CONTACTS`, any case.

    Returns:
        The step limit, s: 0.01 for ``authors``, 5e-4 for ``stiff``.

    Raises:
        ValueError: an unknown name (:func:`check_contact`).
    """
    return contact_solref(contact)[0] / TIMECONST_PER_TIMESTEP
