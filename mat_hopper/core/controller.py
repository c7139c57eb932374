"""The Raibert-style hopping controller of the reference hopper.

One readable scalar controller, :func:`controller_step`, evaluated every
physics step. It is compiled by numba for the fast rollout loop; its plain
Python original (``controller_step.py_func``) runs the same arithmetic for
tests and debugging, and both give the same trajectory.

Four parts (paper section IV-B, spec "Controller"):

- stance/flight state machine with a phase lock, which also adapts the
  thrust once per hop from the last hop height;
- foot placement in flight: a hip PD towards the inverse kinematics of the
  foot position that brings the base to the desired velocity;
- attitude correction in stance: hip torques against body roll and pitch;
- thrust: a constant force on the foot spring while rising in stance.

Hip controls are in actuator space, before the gear: the joint torque is
gear (600) x control, which MuJoCo computes as ``qfrc_actuator``.

When each reading is taken (``SENSOR_TIMINGS``; docs/reference-hopper.md).
The authors' loop reads ``d.sensordata``, computes the control, then calls
``mj_step``; MuJoCo fills ``sensordata`` inside ``mj_step`` *before* it
integrates. So at physics step i (state s_i) their controller sees:

- touch force, base position, orientation quaternion, gyro and linear
  velocity of state s_{i-1} (one physics step, 0.1 ms, old; the touch
  force is the ground reaction computed with the previous control);
- hip angles and rates of state s_i (read from ``qpos``/``qvel``).

That is the default, ``"authors"`` (latency 1). ``"fresh"`` (latency 0)
reads the base from s_i; the touch force cannot be fresher than s_{i-1}
since it depends on the control being computed. An integer latency L
generalises both: base readings of s_{i-L}, touch of s_{i-max(L,1)}, hips
always current. Before the first step every lagged reading is the start
state's (the hopper is at rest there). The rollout loop implements this
(``mat_hopper/core/_loop.py``); the controller below is timing-agnostic.

What the hop height is measured from (:data:`APEX_REFERENCES`, the setting
``SimSettings.apex_reference``). The thrust adapts from the last hop
height, the highest base z since the touchdown before, less the state's
reference height ``S_GROUND_Z``:

- ``"world"`` (default, the authors' controller): the reference stays 0, so
  the apex is regulated in world z. On the 2 deg ramp (3.5 % grade) the
  ground rises under the hopper and its height above the ground shrinks as
  it climbs;
- ``"ground"``: at each lift-off the rollout loop sets the reference to the
  terrain height under the foot (:func:`mat_hopper.core.terrain.terrain_height_at`),
  so the apex is regulated above the ground the hop leaves from.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, fields
from typing import NamedTuple

import numba
import numpy as np

from ..util.parsing import did_you_mean, is_real, parse_name
from . import reference as ref

FLIGHT, STANCE = 0, 1
NO_EVENT, TOUCHDOWN, LIFTOFF = 0, 1, 2

# Controller state (float64 array): indices, named.
S_PHASE = 0  # FLIGHT or STANCE
S_T_SWITCH = 1  # s, time of the last phase switch
S_THRUST = 2  # N, current thrust F
S_Z_MAX = 3  # m, highest base z since the last touchdown
S_LAST_HEIGHT = 4  # m, last hop height (nan before the first)
S_LIFTOFFS = 5  # count of lift-offs so far
S_TOUCHDOWNS = 6  # count of touchdowns so far
S_GROUND_Z = 7  # m, the height the hop height is measured from (0 in world z; module doc)
STATE_SIZE = 8

# Controller outputs (float64 array): controls, then hip targets for logging.
O_HIP_Y, O_HIP_X, O_THRUST = 0, 1, 2  # actuator controls
O_TARGET_Y, O_TARGET_X = 3, 4  # rad, IK hip targets
O_TARGET_RATE_Y, O_TARGET_RATE_X = 5, 6  # rad/s
OUT_SIZE = 7


HOP_HEIGHT_RANGE_M = (0.7, 3.0)  # accepted hop-height targets (base z at the apex)

# What the apex is measured from (module doc): name -> what it means.
APEX_REFERENCES = {
    "world": "the apex in world z (the authors' controller)",
    "ground": "the apex above the terrain under the foot at lift-off",
}
DEFAULT_APEX_REFERENCE = "world"


def check_apex_reference(apex_reference) -> str:
    """The apex reference named (case-insensitive, blanks trimmed;
    :func:`mat_hopper.util.parsing.parse_name`), as spelled in :data:`APEX_REFERENCES`.

    Args:
        apex_reference: ``"world"`` or ``"ground"``, any case.

    Returns:
        The name as spelled in :data:`APEX_REFERENCES` (``"Ground"`` gives ``"ground"``).

    Raises:
        ValueError: an empty name or one not in :data:`APEX_REFERENCES`
            (the message names ``apex_reference`` and lists them).
    """
    return parse_name(apex_reference, APEX_REFERENCES, "apex_reference")


@dataclass(frozen=True)
class ControllerSettings:
    """Every gain of the controller; defaults are the reference hopper's
    (docs/reference-hopper.md, "Controller").

    Args:
        phase_lock_s: least time between phase switches, s (0.1).
        thrust_start_n: the thrust F at the start, N (200).
        thrust_adapt_gain: F += gain x (target - last hop height), N/m (100).
        hop_height_target_m: the base's target peak height, m (1.0).
        thrust_min_rise_speed: thrust only while the base rises faster, m/s (0.01).
        velocity_gain_desired: desired local velocity gain, (m/s)/(m/s) (0.2).
        velocity_gain_position: desired local position offset gain, (m/s)/m (0.5).
        velocity_limit_m_s: clamp of the desired velocity, m/s (0.1).
        stance_duration_s: T_st of the foot placement law, s (0.1).
        foot_placement_gain: K1 of the foot placement law, s (0.05).
        leg_length_m: hip-to-toe length the inverse kinematics assumes, m (0.61).
        flight_kp, flight_kd: hip PD in flight, per rad and per rad/s before the gear (10, 0.1).
        stance_kp, stance_kd: attitude correction in stance, per rad and per rad/s before the gear (4, 1).

    Raises:
        ValueError: a gain that is not finite, negative, or unphysical (naming it).
    """

    phase_lock_s: float = ref.PHASE_LOCK_S
    thrust_start_n: float = ref.THRUST_START_N
    thrust_adapt_gain: float = ref.THRUST_ADAPT_GAIN
    hop_height_target_m: float = ref.HOP_HEIGHT_TARGET
    thrust_min_rise_speed: float = ref.THRUST_MIN_RISE_SPEED
    velocity_gain_desired: float = ref.VELOCITY_GAIN_DESIRED
    velocity_gain_position: float = ref.VELOCITY_GAIN_POSITION
    velocity_limit_m_s: float = ref.VELOCITY_LIMIT
    stance_duration_s: float = ref.STANCE_DURATION_S
    foot_placement_gain: float = ref.FOOT_PLACEMENT_GAIN
    leg_length_m: float = ref.LEG_LENGTH_CONTROLLER
    flight_kp: float = ref.FLIGHT_KP
    flight_kd: float = ref.FLIGHT_KD
    stance_kp: float = ref.STANCE_KP
    stance_kd: float = ref.STANCE_KD

    def __post_init__(self):
        for name, value in asdict(self).items():
            if not is_real(value) or not math.isfinite(value):
                raise ValueError(f"controller setting {name} must be a finite number, got {value!r}")
        if self.leg_length_m <= 0:
            raise ValueError(f"leg_length_m must be > 0 m, got {self.leg_length_m!r}")
        lo, hi = HOP_HEIGHT_RANGE_M
        if not lo <= self.hop_height_target_m <= hi:
            raise ValueError(
                f"hop_height_target_m must be in [{lo:g}, {hi:g}] m (the base stands at about "
                f"0.6 m; the paper's target is 1 m), got {self.hop_height_target_m!r}"
            )
        for name in ("phase_lock_s", "thrust_start_n", "thrust_adapt_gain", "stance_duration_s"):
            if getattr(self, name) < 0:
                raise ValueError(f"controller setting {name} must be >= 0, got {getattr(self, name)!r}")

    def gains(self) -> Gains:
        """These settings as the compiled code reads them (floats, by name)."""
        return Gains(**{name: float(v) for name, v in asdict(self).items()})


# The compiled controller reads its settings from a NamedTuple (numba
# compiles attribute access on it); its fields are generated from
# ControllerSettings, so the two can never drift apart.
Gains = NamedTuple("Gains", [(f.name, float) for f in fields(ControllerSettings)])
Gains.__doc__ = "ControllerSettings as the compiled code sees them (floats, same field names)."

# --- when the readings are taken (module doc) ---------------------------------
SENSOR_TIMINGS = {"fresh": 0, "authors": ref.SENSOR_LATENCY_STEPS}
DEFAULT_SENSOR_TIMING = "authors"
MAX_SENSOR_LATENCY_STEPS = 1000  # 0.1 s at the paper's step: far beyond any study here
LATENCY_PREFIX = "latency-"


class SensorTiming(int):
    """When the controller reads the base sensors: an integer latency in
    physics steps that carries its canonical name.

    ``int(t)`` is the latency (what the rollout loop and the batch kernels
    use); ``t.name`` and ``str(t)`` the name recorded in every result
    (cache key, table, figure): ``"fresh"`` (0), ``"authors"`` (1, the
    default) or ``"latency-L"``. Build it once, from whatever the user
    gave, and pass it on: no call site converts again.

    Args:
        timing: a name (``"authors"``, ``"fresh"``, ``"latency-L"``; any
            case), an integer latency L in [0, 1000] physics steps, or a
            SensorTiming (returned as is).

    Raises:
        ValueError: for an unknown name, a bool, a float or a latency
            outside [0, 1000].

    >>> t = SensorTiming("authors")
    >>> int(t), t.name, SensorTiming(5).name, f"{SensorTiming('FRESH')}"
    (1, 'authors', 'latency-5', 'fresh')
    """

    def __new__(cls, timing=DEFAULT_SENSOR_TIMING):
        if type(timing) is cls:
            return timing
        return super().__new__(cls, _latency(timing))

    @property
    def name(self) -> str:
        """The canonical name: "fresh", "authors" or "latency-L"."""
        lat = int(self)
        for name, steps in SENSOR_TIMINGS.items():
            if steps == lat:
                return name
        return f"{LATENCY_PREFIX}{lat}"

    def key_value(self) -> str:
        """How a cache key records it (:func:`mat_hopper.util.keys.settings_key`): by name."""
        return self.name

    @property
    def latency_steps(self) -> int:
        """Physics steps by which the base readings lag (a plain int)."""
        return int(self)

    def __str__(self) -> str:
        return self.name

    # A timing equals its latency and its names: ``t == "authors"`` and ``t == 1``
    # both hold for the default, so code comparing against either never
    # silently reads False. The hash is the latency's (as int's); a set mixing
    # names and timings is the one place the two differ.
    def __eq__(self, other):
        if isinstance(other, str):
            try:
                return int(self) == _latency(other)
            except ValueError:
                return False
        return int.__eq__(self, other)

    def __ne__(self, other):
        result = self.__eq__(other)
        return result if result is NotImplemented else not result

    __hash__ = int.__hash__

    def __format__(self, spec: str) -> str:
        if spec and spec[-1] in "bcdeEfFgGnoxX%":  # a number format: the latency
            return format(int(self), spec)
        return format(self.name, spec)

    def __repr__(self) -> str:
        return f"SensorTiming({self.name!r})"

    def __reduce__(self):
        return (SensorTiming, (int(self),))


def _latency(timing) -> int:
    """The latency (physics steps) of a timing name or integer; ValueError otherwise."""
    if isinstance(timing, str):
        name = timing.strip().lower()
        if name in SENSOR_TIMINGS:
            return SENSOR_TIMINGS[name]
        digits = name[len(LATENCY_PREFIX) :]
        if name.startswith(LATENCY_PREFIX) and digits.isascii() and digits.isdigit():  # ASCII digits only (not "٣")
            timing = int(digits)
        else:
            hint = did_you_mean(name, SENSOR_TIMINGS)
            raise ValueError(
                f"unknown sensor timing {timing!r}; accepted: {', '.join(SENSOR_TIMINGS)}, "
                f"'latency-L' or an integer L of physics steps in [0, {MAX_SENSOR_LATENCY_STEPS}]"
                + (f"; {hint}" if hint else "")
            )
    if isinstance(timing, (bool, np.bool_)) or not isinstance(timing, (int, np.integer)):
        raise ValueError(
            f"sensor timing must be a name ({', '.join(SENSOR_TIMINGS)}) or an integer latency "
            f"in physics steps, got {timing!r}"
        )
    if not 0 <= timing <= MAX_SENSOR_LATENCY_STEPS:
        raise ValueError(f"sensor latency must be in [0, {MAX_SENSOR_LATENCY_STEPS}] physics steps, got {timing}")
    return int(timing)


def initial_state(settings: ControllerSettings) -> np.ndarray:
    """Fresh controller state: in flight, thrust at its start, the hop
    height measured from z = 0 (``S_GROUND_Z``; module doc). The phase
    lock's clock starts at t = 0, as in the authors' loop, so no switch can
    happen in the first ``phase_lock_s`` of a run.

    Args:
        settings: the controller's gains; only ``thrust_start_n`` (N) is read.

    Returns:
        A float64 array of length :data:`STATE_SIZE`: phase FLIGHT, last
        switch at 0 s, thrust ``thrust_start_n`` N, highest z -inf, last hop
        height nan, lift-off and touchdown counts 0, reference height 0 m.
    """
    s = np.zeros(STATE_SIZE)
    s[S_PHASE] = FLIGHT
    s[S_T_SWITCH] = 0.0
    s[S_THRUST] = settings.thrust_start_n
    s[S_Z_MAX] = -np.inf
    s[S_LAST_HEIGHT] = np.nan
    return s


@numba.njit(cache=True)
def euler_zyx(quat):
    """Roll, pitch, yaw (rad) of a quaternion (w, x, y, z), Z-Y-X convention."""
    w, x, y, z = quat[0], quat[1], quat[2], quat[3]
    roll = math.atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y))
    sp = 2.0 * (w * y - z * x)
    sp = min(1.0, max(-1.0, sp))
    pitch = math.asin(sp)
    yaw = math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
    return roll, pitch, yaw


@numba.njit(cache=True)
def _clamp(v, limit):
    return min(limit, max(-limit, v))


@numba.njit(cache=True)
def update_phase(t, touch, z, vz, g, state):
    """Advance the stance/flight state machine; adapt thrust at touchdown.

    The hop height is the highest z since the last touchdown less
    ``state[S_GROUND_Z]`` (module doc). Returns NO_EVENT, TOUCHDOWN or LIFTOFF."""
    if z > state[S_Z_MAX]:
        state[S_Z_MAX] = z
    if t - state[S_T_SWITCH] < g.phase_lock_s:
        return NO_EVENT
    if state[S_PHASE] == FLIGHT and touch > 0.0 and vz < 0.0:
        state[S_PHASE] = STANCE
        state[S_T_SWITCH] = t
        state[S_TOUCHDOWNS] += 1.0
        if state[S_LIFTOFFS] > 0.0:  # the very first touchdown adapts nothing
            height = state[S_Z_MAX] - state[S_GROUND_Z]  # exactly S_Z_MAX in world z (a reference of 0)
            state[S_LAST_HEIGHT] = height
            # Kept physical: the foot actuator pushes, it never pulls the leg
            # in (a thrust adapted below 0 N would). With the paper's 1 m
            # target F stays near 200-400 N and this bound is never reached.
            state[S_THRUST] = max(0.0, state[S_THRUST] + g.thrust_adapt_gain * (g.hop_height_target_m - height))
        state[S_Z_MAX] = z
        return TOUCHDOWN
    if state[S_PHASE] == STANCE and touch == 0.0 and vz > 0.0:
        state[S_PHASE] = FLIGHT
        state[S_T_SWITCH] = t
        state[S_LIFTOFFS] += 1.0
        return LIFTOFF
    return NO_EVENT


@numba.njit(cache=True)
def controller_step(t, touch, pos, quat, gyro, vel, hip_angle, hip_rate, desired, g, state, out):
    """One control update at time t (s).

    touch: ground force at the toe (N); pos, vel: base position (m) and
    velocity (m/s), world frame; quat: base orientation (w, x, y, z); gyro:
    base angular velocity (rad/s, body frame: roll, pitch, yaw rates);
    hip_angle, hip_rate: (hip_y, hip_x) in rad, rad/s; desired: (x, y, vx,
    vy) of the path in m, m/s. Writes controls and hip targets into out;
    returns the state machine's event.
    """
    event = update_phase(t, touch, pos[2], vel[2], g, state)
    roll, pitch, yaw = euler_zyx(quat)
    roll_rate, pitch_rate = gyro[0], gyro[1]

    # World -> yaw-aligned base frame.
    c, s = math.cos(yaw), math.sin(yaw)
    ex, ey = desired[0] - pos[0], desired[1] - pos[1]
    off_x, off_y = c * ex + s * ey, -s * ex + c * ey
    vdx, vdy = c * desired[2] + s * desired[3], -s * desired[2] + c * desired[3]
    vx, vy = c * vel[0] + s * vel[1], -s * vel[0] + c * vel[1]

    # Velocity to aim for, then the foot placement that reaches it.
    aim_x = _clamp(g.velocity_gain_desired * vdx + g.velocity_gain_position * off_x, g.velocity_limit_m_s)
    aim_y = _clamp(g.velocity_gain_desired * vdy + g.velocity_gain_position * off_y, g.velocity_limit_m_s)
    foot_x = vx * g.stance_duration_s / 2.0 + g.foot_placement_gain * (vx - aim_x)
    foot_y = vy * g.stance_duration_s / 2.0 + g.foot_placement_gain * (vy - aim_y)

    # Inverse kinematics, corrected for body attitude.
    target_y = -math.atan(foot_x / g.leg_length_m) - pitch
    target_x = math.atan(foot_y / g.leg_length_m) - roll
    target_rate_y = -pitch_rate
    target_rate_x = -roll_rate

    if touch > 0.0:  # stance: attitude correction through the hips
        u_y = g.stance_kp * pitch + g.stance_kd * pitch_rate
        u_x = g.stance_kp * roll + g.stance_kd * roll_rate
    else:  # flight: PD to the foot placement targets
        u_y = -g.flight_kp * (hip_angle[0] - target_y) - g.flight_kd * (hip_rate[0] - target_rate_y)
        u_x = -g.flight_kp * (hip_angle[1] - target_x) - g.flight_kd * (hip_rate[1] - target_rate_x)
    thrust = state[S_THRUST] if (touch > 0.0 and vel[2] > g.thrust_min_rise_speed) else 0.0

    out[O_HIP_Y] = u_y
    out[O_HIP_X] = u_x
    out[O_THRUST] = thrust
    out[O_TARGET_Y] = target_y
    out[O_TARGET_X] = target_x
    out[O_TARGET_RATE_Y] = target_rate_y
    out[O_TARGET_RATE_X] = target_rate_x
    return event
