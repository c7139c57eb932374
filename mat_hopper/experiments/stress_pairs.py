"""The stress pairs: each paper gradient beside its controls on shared seeds.

For each of the paper's four gradients (:data:`GRADIENTS`), under each
stiffness convention asked for, one forward run per replicate seed (the
profile's ``replicates``; the same seeds for every leg, so comparisons are
paired) of the gradient, of its mass-matched leg
(:func:`mat_hopper.core.control_legs.mass_matched`: the same leg mass, one
homogeneous fictional material, for the loads) and of titanium (the
catalogue metal nearest in density to the gradients' mean, with its own
S-N curve, for the life). ``contact`` names the foot's contact
(:mod:`mat_hopper.core.contact`): under a bending convention the soft
default lets stiff legs fall, the stiff one does not. The runs go through
the one cache and pool; titanium's serve every gradient. Chapter 8b reads
them with :func:`mat_hopper.analysis.stress_pairs.stress_verdicts`.
"""

from __future__ import annotations

from ..core.behaviours import behaviour
from ..core.contact import DEFAULT_CONTACT
from ..core.control_legs import mass_matched
from ..core.materials import paper_designs, parse_design
from ..core.timestep import is_auto
from .common_step import at_common_step, common_step
from .profiles import check_replicates, get_profile
from .runner import RunSpec

GRADIENTS = ("rho-inc", "rho-dec", "PVC-Ti-SS", "SS-Ti-PVC")
CONVENTIONS = ("paper", "bending")
LEGS = ("gradient", "mass-matched", "titanium")


def stress_pair_tasks(
    profile, conventions=CONVENTIONS, contact: str = DEFAULT_CONTACT, one_step: bool = True, replicates=None
) -> list:
    """RunSpecs of every gradient, its mass-matched leg and titanium (module doc).

    Args:
        profile: a Profile or its name (its replicates, run length and step;
            each convention's step as :meth:`Profile.for_convention` gives it;
            where that is ``"auto"``, a gradient, its mass-matched leg and
            titanium run at one step, :func:`~mat_hopper.experiments.common_step.common_step`).
        conventions: stiffness conventions (canonical names).
        contact: the foot's contact (``authors`` or ``stiff``).
        one_step: where the step is ``"auto"``, run a gradient, its
            mass-matched leg and titanium at one step (their pairs are
            compared); False: each leg at its own (only each leg's own
            outcome is read, e.g. whether it stayed up).
        replicates: seeds 0..n-1 per leg (None: the profile's ``replicates``,
            what a paired verdict needs; a share of runs that stayed up,
            which no test reads, takes the profile's ``figure_replicates``).

    Returns:
        list of RunSpec, forward hopping; labels convention, contact,
        gradient, leg (:data:`LEGS`), design, replicate.

    Raises:
        ValueError: an unknown profile, convention or contact, or replicates < 1.
    """
    profile = get_profile(profile)
    n = profile.replicates if replicates is None else check_replicates(replicates, minimum=1)
    if n < 1:
        raise ValueError(f"replicates must be >= 1, got {replicates!r}")
    conventions = (conventions,) if isinstance(conventions, str) else tuple(conventions)
    if not conventions:
        raise ValueError("conventions must name at least one stiffness convention")
    designs, ti = paper_designs(), parse_design("Ti")
    tasks = []
    for conv in conventions:
        prof = profile.for_convention(conv)
        for name in GRADIENTS:
            g = designs[name]
            trio = (g, mass_matched(g), ti)
            # under "auto" the three legs of a comparison share the step the finest of them needs
            shared = one_step and is_auto(prof.timestep_s)
            step = common_step(trio, conv, contact, prof.sensor_timing.name) if shared else None
            for role, leg in zip(LEGS, trio):
                for seed in range(n):
                    labels = {
                        "convention": conv,
                        "contact": contact,
                        "gradient": name,
                        "leg": role,
                        "design": leg.name,
                        "replicate": seed,
                    }
                    settings = prof.sim_settings(prof.replicate(seed), design=leg, contact=contact)
                    if step is not None:
                        settings = at_common_step(settings, *step)
                    tasks.append(RunSpec(leg, behaviour("forward"), settings, labels))
    return tasks
