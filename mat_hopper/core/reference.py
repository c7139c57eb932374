"""The reference hopper: every number the paper's authors' code fixes.

One source of truth. Geometry, masses, gains, protocol and experiment grids
of the reference hopper (``docs/reference-hopper.md``: each number with
its source) live here and nowhere else; the rest
of the package imports them. Units are SI unless a name says otherwise
(``_deg``, ``_g_cm3``, ``_gpa``).
"""

from __future__ import annotations

import math

# --- Physics options -------------------------------------------------------
GRAVITY_M_S2 = 9.81  # MuJoCo's default gravity, (0, 0, -9.81)
TIMESTEP_S = 1e-4  # the paper's experiments (MuJoCo default 2e-3)
SOLVER_ITERATIONS = 50
SOLVER_TOLERANCE = 1e-10
JOINT_DAMPING_DEFAULT = 1.0  # N s/m or N m s/rad, every joint unless set

# --- Base (torso) ----------------------------------------------------------
BASE_START_Z = 1.2  # m, initial qpos of the base's z slide joint (the base
# body itself sits at the world origin, as in the authors' file)
BASE_CAPSULE_RADIUS = 0.09  # m
BASE_CAPSULE_HALF_LENGTH = 0.12  # m, capsules along x and along y
BASE_CAPSULE_MASS = 7.5  # kg each (two capsules: 15 kg)
CIRCLE_START_X = 0.5  # m, the circle behaviour starts here

# --- Hip -------------------------------------------------------------------
HIP_RANGE_DEG = 70.0  # +- deg, both hip hinges
HIP_STIFFNESS = 20.0  # N m/rad
HIP_DAMPING = 20.0  # N m s/rad
HIP_GEAR = 600.0  # motor gear on hip_y and hip_x

# --- Leg -------------------------------------------------------------------
STUB_RADIUS = 0.03  # m
STUB_LENGTH = 0.05  # m, capsule from the hip down
STUB_DENSITY = 1000.0  # kg/m^3
MATERIAL_RADIUS = 0.025  # m, every material capsule
MATERIAL_LENGTH = 0.3  # m of material in all, split evenly
REFERENCE_SEGMENTS = 3  # the paper's leg
FOOT_UPPER_LENGTH = 0.05  # m, capsule under the last segment
FOOT_UPPER_DENSITY = 1000.0  # kg/m^3
FOOT_RADIUS = 0.04  # m
FOOT_LENGTH = 0.2  # m, capsule below the foot spring
FOOT_MASS = 0.5  # kg
FOOT_SPRING_STIFFNESS = 8000.0  # N/m
FOOT_SPRING_DAMPING = 10.0  # N s/m
FOOT_SPRING_RANGE = 0.1  # +- m
FOOT_CONDIM = 6
TOE_SITE_RADIUS = 0.05  # m; must enclose the foot's contact point
LEG_LENGTH_CONTROLLER = 0.61  # m, hip-to-toe length the IK assumes
# Masses MuJoCo computes for the 3-segment reference leg (kg, whole robot).
MASS_MD_KG = 16.90
MASS_SS_KG = 23.77

# --- Ground and ramp -------------------------------------------------------
RAMP_HALF_SIZE = (2.0, 0.5, 0.1)  # m
RAMP_CENTER_X = 2.0  # m
RAMP_CENTER_Z = -0.03  # m, exact in the authors' file (not a rounded value; the top
# face meets the ground about 0.2 mm above x = 0)
RAMP_GRADE_DEG = 2.0  # deg pitch: tan(2 deg) = 3.5 % grade
RAMP_FRICTION = (1.0, 0.005, 0.0001)

# --- Modulus to stiffness, the authors' way -------------------------------
# k = 3 E I / L^3 with E the bare number of GPa, I = pi * r * 4 (sic) with
# r = 0.025 m, and L = 0.01 m. Net: 9.4248e5 N/m per GPa.
PAPER_I = math.pi * MATERIAL_RADIUS * 4
PAPER_L = 0.01
PAPER_STIFFNESS_PER_GPA = 3.0 * PAPER_I / PAPER_L**3  # N/m per GPa

# --- Controller ------------------------------------------------------------
# When the controller's readings are taken. The authors' loop is: read
# d.sensordata, control, mj_step. MuJoCo fills sensordata inside mj_step
# *before* integrating, so the base sensors (touch, position, orientation,
# gyro, velocity) the controller sees are one physics step old, while the
# hip angles and rates (read from qpos/qvel) are current.
SENSOR_LATENCY_STEPS = 1  # physics steps by which the base sensors lag (authors' loop)
PHASE_LOCK_S = 0.1  # min time between phase switches
THRUST_START_N = 200.0  # N
THRUST_ADAPT_GAIN = 100.0  # N per m of hop-height error
HOP_HEIGHT_TARGET = 1.0  # m, max base z per hop
THRUST_MIN_RISE_SPEED = 0.01  # m/s, thrust only while rising faster
VELOCITY_GAIN_DESIRED = 0.2  # (m/s)/(m/s), desired local velocity
VELOCITY_GAIN_POSITION = 0.5  # (m/s)/m, desired local position offset
VELOCITY_LIMIT = 0.1  # m/s, clamp of the desired velocity
STANCE_DURATION_S = 0.1  # T_st in the foot placement law
FOOT_PLACEMENT_GAIN = 0.05  # s, K1
FLIGHT_KP = 10.0  # per rad, before the gear
FLIGHT_KD = 0.1  # per rad/s, before the gear
STANCE_KP = 4.0  # attitude correction, before the gear
STANCE_KD = 1.0

# --- Behaviours ------------------------------------------------------------
SPEED_M_S = 0.05  # commanded speed, forward, ramp, circle
CIRCLE_RADIUS = 0.5  # m

# --- Protocol --------------------------------------------------------------
DURATION_S = 60.0  # simulated seconds per run
TRANSIENT_S = 20.0  # hop cycles starting earlier are not scored
DIVERGENCE_QACC = 1e6  # |qacc| above this is numerical divergence
STABLE_MIN_BASE_Z = 0.1  # m, a stable run ends with the base above

# --- Materials (density g/cm^3, modulus GPa; None = rigid) ---------------
MONO_MATERIALS = {
    "MD": (1.0, None),
    "PVC": (1.39, 4.0),
    "Al": (2.7, 70.0),
    "Ti": (4.43, 120.0),
    "SS": (8.0, 193.0),
}

# --- Experiments -----------------------------------------------------------
SWEEPS = {  # one property at a time, forward hopping
    "PVC": {"density": (1.10, 1.39, 1.45, 1.90, 2.5), "modulus": (0.1, 0.45, 2.01, 4, 9)},
    "Al": {"density": (2.7, 3.95, 8.66), "modulus": (20, 62.14, 70)},
    "Ti": {"density": (2.0, 4.24, 4.43, 8.97, 19.0), "modulus": (18, 63.76, 120, 225.85, 800)},
    "SS": {"density": (2.0, 4.31, 8.0, 9.28, 20.0), "modulus": (15, 60.82, 193, 246.62, 1000)},
}
GRADIENT_DENSITIES = (1.39, 4.43, 8.0)  # g/cm^3, rho-inc from base to foot
GRADIENT_MODULUS_GPA = 70.0  # every segment of rho-inc / rho-dec
STABILITY_GRID_SIZE = 20
STABILITY_DENSITY_RANGE = (1.39, 8.0)  # g/cm^3, log-spaced
STABILITY_MODULUS_RANGE = (4.0, 340.0)  # GPa, log-spaced
STABILITY_TIMESTEP_RANGE = (1e-3, 1e-5)  # s, 20 log-spaced tries
STABILITY_TEST_DURATION_S = 2.0  # s of static hopping per try

# --- The paper's quantitative claims (docs/reference-hopper.md, "The paper's claims")
# Percent changes are of means against a baseline design (negative: lower).
DYNAMIC_BEHAVIOURS = ("forward", "ramp", "circle")  # the paper's behaviours 2-4
CLAIM_HOP_HEIGHT_M = 1.0  # every design's mean hop height
CLAIM_SS_TRACKING_PCT = -55.0  # SS vs MD, at least this on every behaviour
CLAIM_SS_POWER_MAX_PCT = 193.0  # SS vs MD, the largest increase (dynamic behaviours)
CLAIM_LOW_MODULUS_GPA = 9.0  # moduli <= this track worse than ...
CLAIM_HIGH_MODULUS_GPA = 20.0  # ... moduli >= this
CLAIM_RAMP_RHO_INC_TRACKING_PCT = -82.0  # ramp, rho-inc vs MD
CLAIM_RAMP_RHO_INC_POWER_PCT = 123.0
CLAIM_RAMP_SS_TRACKING_PCT = -72.0  # ramp, SS vs MD
CLAIM_RAMP_SS_POWER_PCT = 193.0
CLAIM_HEADLINE_TRACKING_PCT = -35.0  # ramp, rho-inc vs SS (the abstract)
CLAIM_HEADLINE_POWER_PCT = -23.0
CLAIM_STABLE_TIMESTEP_S = {"PVC": 1e-3, "Al": 1e-4, "SS": 1e-4}  # about, per material
