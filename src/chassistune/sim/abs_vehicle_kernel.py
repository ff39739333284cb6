"""Compiled closed loop of the 7-DOF vehicle ABS (design.md 3.3) over a population of candidates.

One kernel serves every wheel controller (the law's kind selects it, through the one dispatch
generated from the registry, `controllers.laws.dispatch`) and both paths: a batch of
n gain rows, or one row with a trace (a single run is a batch of one).

Plant (`chassistune.plants.abs_vehicle`): body (vx, vy, r), position and heading (X, Y, psi), an
optional driver steering angle delta, and per wheel its spin w, brake pressure q and pressure
rate (K/(s(Ts+1)) actuator, q held in [0, q_max]); the load/force loop is solved exactly at every
evaluation (closed form in a straight line, Newton's method otherwise).
    m (dvx/dt - vy r) = sum Fx_i,  m (dvy/dt + vx r) = sum Fy_i,  Iz dr/dt = sum x_i Fy_i - y_i Fx_i
    J dw_i/dt = -R Fx_i - kq q_i   (w_i >= 0: held at 0 while the brake exceeds the tire torque)
Wheel laws on e_i = S*_i - S_i (S_i = (u_i - w_i R)/|V_i| clipped to [0, 1], S*_i the optimal
slip of the surface under wheel i): the continuous PID of the single wheel (filtered derivative,
conditional integration) u = u0 + kp e + ki z + kd N (e - xf), plus the sampled part u0 of the
switching laws (none, threshold) and the sampled gain schedule of the fuzzy PID (period ts_s).
Select-low: both rear channels get e = min(e_rl, e_rr) (the wheel with the larger slip), hence
bitwise equal pressures.

Integration: classic RK4 at a fixed step over all states; the CG path length and the slip
integrals by quadrature of step-end values (as the single wheel); the surfaces under the wheels
and their target slips switch at step ends from the contact points' global positions; the stop
at v_stop (CG speed) is located by linear interpolation inside the last step, and the end metrics
(stop_x_m, the end heading and lateral offset) and the trace's last row are the state there: the
speeds, wheel and controller states linear over the step, X, Y and the heading their integrals
(`_at_stop`), on the surfaces of that step. A wheel's lock time is located the same way, where
its margin w R - lock_ratio |V|, linear over the step, crosses 0.

Lanes (the design of `abs_wheel_kernel`). Every per-candidate quantity lives in ONE
flat array `st` of rows of LANES values (row r of lane l at r * LANES + l). Each iteration runs
one fused RK4 step per lane (`_lane_step`) for a whole number of VECTOR-wide blocks: the
straight-line case (no yaw, lateral velocity, heading or steering; loads in closed form), all
four stages in registers, branch-free, stored by select only where every stage and the step's
end were straight. Lanes where that case does not hold (split-mu, a driver steering, a wheel
unloaded), and the step in which a run stops, are redone by a scalar pass (`_general_step`):
each stage straight where it holds, else `_rhs` with the loads by Newton's method, in the same
formulas and order, so that a lane's numbers do not depend on the path, the lane or the
population. Sampled laws tick in a scalar pass before the step at each lane's own sample
instants; a finished lane is refilled from the queue or, when it is empty, filled with the last
live lane (live lanes stay packed in front).

Compilation: the entry point (`entry_point`) is a closure over the registry's fingerprint (on
which numba keys its disk cache); it passes the fingerprint to the lane loop (`_simulate`) as a
literal argument, so that the loop, the ticks and the lane fill (which dispatch on the laws) and
the vector loop compile as cached functions of their own, each keyed on its arguments' types.

No reference counting. The entry point (`entry_point`) and its scalar passes (the functions not
inlined) are compiled without numba's runtime (`_nrt=False`): the caller passes every array the
kernel works in as one tuple (`scratch()`), the kernel resets it, and nothing is allocated. With the
runtime, every inlined call that took arrays (a sampled law's tick, the general step, a trace
row) paid an atomic increment and decrement per array (141 and 262 such calls in the compiled
code, none now): fuzzy PID 590 -> 940 sims/s, threshold 930 -> 2190 on one core (paper-deffao,
dry concrete), every number bitwise unchanged.
"""

from __future__ import annotations

import math
from typing import Any

import numba
import numpy as np

from chassistune._branchfree import clip, fmax, fmin, select
from chassistune.controllers.laws import registry as laws
from chassistune.controllers.laws.dispatch import law_sampled, law_start, law_tick
from chassistune.controllers.pid import pid_step
from chassistune.layout import Layout, Slot
from chassistune.plants.abs_vehicle import (
    GEO_A,
    GEO_B,
    GEO_FZ0,
    GEO_X,
    GEO_Y,
    N_WORK,
    SF_FALL0,
    SF_FALL1,
    SF_RISE,
    SF_ST,
    SF_TARGET,
    WK_CS,
    WK_FXB,
    WK_FXW,
    WK_FYB,
    WK_FZ,
    WK_SN,
    WK_SX,
    WK_VR,
    solve_loads,
)
from chassistune.plants.vehicle_roads import ROAD_MU_JUMP, ROAD_SPLIT
from chassistune.sim import abs_wheel_layout as WL
from chassistune.sim.integrate import (
    crossing_fraction,
    error_integrals,
    rk4_point,
    rk4_update,
    trapezoid,
)
from chassistune.sim.lanes import close_lane

_NO_REFCOUNT: dict[str, Any] = {
    "cache": True,
    "nogil": True,
    "error_model": "numpy",
    "_nrt": False,
}
"""Options of the entry point and its scalar passes (the functions not inlined): compiled without
numba's runtime, hence no reference counting (`_nrt` is not in numba's type stubs)."""

WHEELS = ("fl", "fr", "rl", "rr")
CONTROLLER_LAYOUT = WL.CONTROLLER
"""The controller vector: the single wheel's (sample period, amplitude, threshold settings)."""
Q_TS = CONTROLLER_LAYOUT["ts_s"]

PLANT_LAYOUT = Layout(
    "abs-vehicle plant",
    (
        Slot("mass_kg", "kg"),
        Slot("yaw_inertia_kg_m2", "kg m^2"),
        Slot("wheel_inertia_kg_m2", "kg m^2"),
        Slot("wheel_radius_m", "m"),
        Slot("v0_m_s", "m/s"),
        Slot("actuator_gain", "preset unit/s"),
        Slot("actuator_tau_s", "s"),
        Slot("brake_gain", "N m/preset unit"),
        Slot("q_max", "preset unit"),
        Slot("v_stop_m_s", "m/s"),
        Slot("t_max_s", "s"),
        Slot("dt_s", "s"),
        Slot("lock_ratio", "-"),
        Slot("min_speed_m_s", "m/s"),
        Slot("hopeless_m", "m", "stop a candidate once its path exceeds this"),
        Slot("n_filter", "rad/s", "PID derivative filter coefficient"),
        Slot("road_kind", "-", "0 uniform, 1 mu-jump, 2 split-mu"),
        Slot("x_jump_global_m", "m", "global X of the mu jump (CG starts at 0)"),
        Slot("split_y_m", "m", "global Y of the split line"),
        Slot(
            "split_by_road",
            "-",
            "1: split-mu surface from the contact point's global Y; 0: by "
            "the wheel's side of the car",
        ),
        Slot("driver", "-", "1: counter-steering driver, 0: steering fixed at 0"),
        Slot("heading_gain", "rad/rad"),
        Slot("yaw_rate_gain_s", "s"),
        Slot("max_steer_rad", "rad"),
        Slot("steer_tau_s", "s"),
        Slot("select_low", "-", "1: one rear channel on min(e_rl, e_rr)"),
        Slot("axle_gains", "-", "1: gains (front row, rear row) per axle"),
        Slot("yaw_window_s", "s", "window of the yaw metrics"),
    ),
)
GEOMETRY_LAYOUT = Layout(
    "abs-vehicle geometry rows (columns fl, fr, rl, rr)",
    (
        Slot("x_m", "m", "wheel position forward of the CG"),
        Slot("y_m", "m", "wheel position left of the CG"),
        Slot("static_load_n", "N", "Fz0_i"),
        Slot("load_per_ax", "N/(m/s^2)", "A_i"),
        Slot("load_per_ay", "N/(m/s^2)", "B_i"),
    ),
)
STATE_LAYOUT = Layout(
    "abs-vehicle state rows",
    (
        Slot("vx", "m/s"),
        Slot("vy", "m/s"),
        Slot("yaw_rate", "rad/s"),
        Slot("x", "m"),
        Slot("y", "m"),
        Slot("heading", "rad"),
        Slot("steer", "rad"),
        *(Slot(f"w_{w}", "rad/s") for w in WHEELS),
        *(Slot(f"q_{w}", "unit") for w in WHEELS),
        *(Slot(f"qrate_{w}", "unit/s") for w in WHEELS),
        *(Slot(f"z_{w}", "s") for w in WHEELS),
        *(Slot(f"xf_{w}", "-") for w in WHEELS),
    ),
)
METRIC_LAYOUT = Layout(
    "abs-vehicle metrics",
    (
        Slot("status", "-", "0 stopped, 1 hopeless, 2 timeout, 3 diverged"),
        Slot("stop_time_s", "s"),
        Slot("stop_distance_m", "m", "CG path length"),
        Slot("stop_x_m", "m", "global X of the CG at the stop"),
        Slot("slip_iae", "s", "sum over the wheels"),
        Slot("slip_itae", "s^2", "sum over the wheels"),
        Slot("slip_ise", "s", "sum over the wheels"),
        Slot("locked_time_s", "s", "sum over the wheels of the time locked while moving"),
        Slot("yaw_rate_peak_1s_rad_s", "rad/s", "signed yaw rate of largest |r| in the window"),
        Slot("heading_1s_deg", "deg", "heading at the end of the window"),
        Slot("lateral_offset_1s_m", "m", "global Y of the CG at the end of the window"),
        Slot("peak_yaw_rate_rad_s", "rad/s", "signed peak before a spin, or of the whole run"),
        Slot("spun", "-", "1 when |heading| reached 90 degrees"),
        Slot("spin_time_s", "s", "when |heading| reached 90 degrees (NaN: never)"),
        Slot("heading_change_deg", "deg", "heading at the end"),
        Slot("lateral_offset_m", "m", "global Y of the CG at the end"),
        Slot("all_locked_time_s", "s", "first time all four wheels stand still (NaN: never)"),
        Slot("all_locked_speed_m_s", "m/s", "CG speed then"),
        Slot("all_locked_distance_m", "m", "CG path length then"),
        *(Slot(f"mean_slip_{w}", "-") for w in WHEELS),
        *(
            Slot(
                f"lock_time_{w}_s",
                "s",
                "first time w R < lock_ratio |V|, located inside its step (NaN: never)",
            )
            for w in WHEELS
        ),
        Slot("load_iterations_max", "-", "most Newton iterations of one load solve"),
        Slot("n_trace", "-", "trace rows written"),
    ),
)
TRACE_LAYOUT = Layout(
    "abs-vehicle trace",
    (
        Slot("time_s", "s"),
        Slot("vx_m_s", "m/s"),
        Slot("vy_m_s", "m/s"),
        Slot("speed_m_s", "m/s"),
        Slot("yaw_rate_rad_s", "rad/s"),
        Slot("heading_rad", "rad"),
        Slot("x_m", "m"),
        Slot("y_m", "m"),
        Slot("steer_rad", "rad"),
        Slot("ax_m_s2", "m/s^2"),
        Slot("ay_m_s2", "m/s^2"),
        Slot("distance_m", "m"),
        *(Slot(f"wheel_speed_{w}_m_s", "m/s") for w in WHEELS),
        *(Slot(f"slip_{w}", "-") for w in WHEELS),
        *(Slot(f"target_slip_{w}", "-") for w in WHEELS),
        *(Slot(f"load_{w}_n", "N") for w in WHEELS),
        *(Slot(f"brake_torque_{w}_n_m", "N m") for w in WHEELS),
        *(Slot(f"fx_{w}_n", "N", "wheel-frame longitudinal tire force") for w in WHEELS),
        *(Slot(f"surface_{w}", "-", "index of the surface under the wheel") for w in WHEELS),
    ),
)

P_MASS = PLANT_LAYOUT["mass_kg"]
P_IZ = PLANT_LAYOUT["yaw_inertia_kg_m2"]
P_J = PLANT_LAYOUT["wheel_inertia_kg_m2"]
P_R = PLANT_LAYOUT["wheel_radius_m"]
P_V0 = PLANT_LAYOUT["v0_m_s"]
P_K = PLANT_LAYOUT["actuator_gain"]
P_TAU = PLANT_LAYOUT["actuator_tau_s"]
P_KQ = PLANT_LAYOUT["brake_gain"]
P_QMAX = PLANT_LAYOUT["q_max"]
P_VSTOP = PLANT_LAYOUT["v_stop_m_s"]
P_TMAX = PLANT_LAYOUT["t_max_s"]
P_DT = PLANT_LAYOUT["dt_s"]
P_LOCK = PLANT_LAYOUT["lock_ratio"]
P_VMIN = PLANT_LAYOUT["min_speed_m_s"]
P_HOPELESS = PLANT_LAYOUT["hopeless_m"]
P_NF = PLANT_LAYOUT["n_filter"]
P_ROAD = PLANT_LAYOUT["road_kind"]
P_XJUMP = PLANT_LAYOUT["x_jump_global_m"]
P_YSPLIT = PLANT_LAYOUT["split_y_m"]
P_SPLIT_ROAD = PLANT_LAYOUT["split_by_road"]
P_DRIVER = PLANT_LAYOUT["driver"]
P_KPSI = PLANT_LAYOUT["heading_gain"]
P_KR = PLANT_LAYOUT["yaw_rate_gain_s"]
P_DMAX = PLANT_LAYOUT["max_steer_rad"]
P_STAU = PLANT_LAYOUT["steer_tau_s"]
P_SELECT_LOW = PLANT_LAYOUT["select_low"]
P_AXLE = PLANT_LAYOUT["axle_gains"]
P_WINDOW = PLANT_LAYOUT["yaw_window_s"]
N_PLANT = len(PLANT_LAYOUT)

G_X = GEOMETRY_LAYOUT["x_m"]
G_Y = GEOMETRY_LAYOUT["y_m"]
G_FZ0 = GEOMETRY_LAYOUT["static_load_n"]
G_A = GEOMETRY_LAYOUT["load_per_ax"]
G_B = GEOMETRY_LAYOUT["load_per_ay"]
N_GEOMETRY = len(GEOMETRY_LAYOUT)
if (G_X, G_Y, G_FZ0, G_A, G_B) != (GEO_X, GEO_Y, GEO_FZ0, GEO_A, GEO_B):  # pragma: no cover
    raise RuntimeError("GEOMETRY_LAYOUT must declare the rows of plants.abs_vehicle.geometry")

S_VX = STATE_LAYOUT["vx"]
S_VY = STATE_LAYOUT["vy"]
S_YR = STATE_LAYOUT["yaw_rate"]
S_X = STATE_LAYOUT["x"]
S_Y = STATE_LAYOUT["y"]
S_PSI = STATE_LAYOUT["heading"]
S_DELTA = STATE_LAYOUT["steer"]
S_W = STATE_LAYOUT["w_fl"]
S_Q = STATE_LAYOUT["q_fl"]
S_QR = STATE_LAYOUT["qrate_fl"]
S_Z = STATE_LAYOUT["z_fl"]
S_XF = STATE_LAYOUT["xf_fl"]
N_STATE = len(STATE_LAYOUT)
K_FLAG = N_STATE
"""Extra row of the stage derivative arrays: 1 where the straight-line pass did not apply."""

M_STATUS = METRIC_LAYOUT["status"]
M_TIME = METRIC_LAYOUT["stop_time_s"]
M_DIST = METRIC_LAYOUT["stop_distance_m"]
M_XSTOP = METRIC_LAYOUT["stop_x_m"]
M_IAE = METRIC_LAYOUT["slip_iae"]
M_ITAE = METRIC_LAYOUT["slip_itae"]
M_ISE = METRIC_LAYOUT["slip_ise"]
M_LOCKED = METRIC_LAYOUT["locked_time_s"]
M_YAWPK1 = METRIC_LAYOUT["yaw_rate_peak_1s_rad_s"]
M_PSI1 = METRIC_LAYOUT["heading_1s_deg"]
M_Y1 = METRIC_LAYOUT["lateral_offset_1s_m"]
M_YAWPK = METRIC_LAYOUT["peak_yaw_rate_rad_s"]
M_SPUN = METRIC_LAYOUT["spun"]
M_SPIN_T = METRIC_LAYOUT["spin_time_s"]
M_PSI_END = METRIC_LAYOUT["heading_change_deg"]
M_Y_END = METRIC_LAYOUT["lateral_offset_m"]
M_ALL_T = METRIC_LAYOUT["all_locked_time_s"]
M_ALL_V = METRIC_LAYOUT["all_locked_speed_m_s"]
M_ALL_D = METRIC_LAYOUT["all_locked_distance_m"]
M_MEAN_SLIP = METRIC_LAYOUT["mean_slip_fl"]
M_LOCK_T = METRIC_LAYOUT["lock_time_fl_s"]
M_ITER = METRIC_LAYOUT["load_iterations_max"]
M_NTRACE = METRIC_LAYOUT["n_trace"]
N_METRICS = len(METRIC_LAYOUT)
STATUS_STOPPED, STATUS_HOPELESS, STATUS_TIMEOUT, STATUS_DIVERGED = 0, 1, 2, 3

T_TIME = TRACE_LAYOUT["time_s"]
T_VX = TRACE_LAYOUT["vx_m_s"]
T_VY = TRACE_LAYOUT["vy_m_s"]
T_SPEED = TRACE_LAYOUT["speed_m_s"]
T_YR = TRACE_LAYOUT["yaw_rate_rad_s"]
T_PSI = TRACE_LAYOUT["heading_rad"]
T_X = TRACE_LAYOUT["x_m"]
T_Y = TRACE_LAYOUT["y_m"]
T_DELTA = TRACE_LAYOUT["steer_rad"]
T_AX = TRACE_LAYOUT["ax_m_s2"]
T_AY = TRACE_LAYOUT["ay_m_s2"]
T_DIST = TRACE_LAYOUT["distance_m"]
T_WV = TRACE_LAYOUT["wheel_speed_fl_m_s"]
T_SLIP = TRACE_LAYOUT["slip_fl"]
T_TARGET = TRACE_LAYOUT["target_slip_fl"]
T_FZ = TRACE_LAYOUT["load_fl_n"]
T_TB = TRACE_LAYOUT["brake_torque_fl_n_m"]
T_FX = TRACE_LAYOUT["fx_fl_n"]
T_SURF = TRACE_LAYOUT["surface_fl"]
N_TRACE = len(TRACE_LAYOUT)

# the wheel laws' gains and held command per wheel, as `_rhs` reads them: law[LAW_*, j, i]
LAW_KP, LAW_KI, LAW_KD, LAW_U0 = range(4)
N_LAW = 4

# scratch rows of one evaluation (columns: the wheels): the physics' work rows, then ours
W_SX, W_VR, W_CS, W_SN, W_FZ, W_FXW, W_FXB, W_FYB = (
    WK_SX,
    WK_VR,
    WK_CS,
    WK_SN,
    WK_FZ,
    WK_FXW,
    WK_FXB,
    WK_FYB,
)
W_SLIP, W_VABS, W_E = N_WORK, N_WORK + 1, N_WORK + 2
N_SCRATCH = N_WORK + 3

LANES = 16
"""Candidates in flight per kernel call (a multiple of VECTOR)."""
VECTOR = 8
"""Lanes per vector iteration (8 doubles: one zmm register; two ymm)."""

# Lane rows (row r of lane l at r * LANES + l): the state (STATE_LAYOUT order), the last step's
# k4 (stage 1 is x + 0 k4, as in a stage-by-stage RK4), the wheel laws (kp, ki, kd, u0 per wheel),
# the surface under each wheel (1.0: the road's second surface), then metrics and bookkeeping;
# the law's memory (`Law.state`) in MEMORY blocks of four wheels, the wheel speeds at the last
# sample.
R_K4 = N_STATE
R_KP = R_K4 + N_STATE
R_KI = R_KP + 4
R_KD = R_KI + 4
R_U0 = R_KD + 4
R_SURF = R_U0 + 4
R_SLIP = R_SURF + 4
R_SINT = R_SLIP + 4
R_LOCK_T = R_SINT + 4
R_LOCK_M0 = R_LOCK_T + 4
R_LOCK_M1 = R_LOCK_M0 + 4
R_MEM = R_LOCK_M1 + 4
R_WS = R_MEM + 4 * laws.MEMORY
(
    R_DIST,
    R_SPEED,
    R_IAE,
    R_ITAE,
    R_ISE,
    R_LOCKED,
    R_ALL_T,
    R_ALL_V,
    R_ALL_D,
    R_YAWPK1,
    R_PSI1,
    R_Y1,
    R_YAWPK,
    R_SPIN_T,
    R_STATUS,
    R_TEND,
    R_STEP,
    R_ENDED,
    R_DONE,
    R_AX,
    R_AY,
    R_ITER,
) = range(R_WS + 4, R_WS + 26)
N_ROWS = R_WS + 26

# the kernel's constants, one tuple (`_constants`): plant, geometry, solver and road
(KC_MASS, KC_FZ0, KC_A, KC_GX, KC_GY) = (0, 1, 5, 9, 13)
(
    KC_RW,
    KC_VMIN,
    KC_KQ,
    KC_NF,
    KC_GAIN,
    KC_QMAX,
    KC_KPSI,
    KC_KR,
    KC_DMAX,
    KC_INV_IZ,
    KC_INV_J,
    KC_INV_TAU,
    KC_INV_ST,
    KC_DRIVER,
    KC_SELECT_LOW,
    KC_KIND,
    KC_XJUMP,
    KC_SPLIT_ROAD,
    KC_YSPLIT,
    KC_VSTOP,
    KC_LOCK,
    KC_HOPELESS,
    KC_WINDOW,
    KC_DT,
    KC_HS,
    KC_H6,
    KC_NSTEPS,
    KC_TTIMEOUT,
) = range(17, 45)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _constants(p, geo):
    """The constants tuple (KC_* entries) of a plant vector and geometry."""
    dt = p[P_DT]
    n_steps = math.ceil(p[P_TMAX] / dt - 1e-9)
    return (
        p[P_MASS],
        geo[G_FZ0, 0],
        geo[G_FZ0, 1],
        geo[G_FZ0, 2],
        geo[G_FZ0, 3],
        geo[G_A, 0],
        geo[G_A, 1],
        geo[G_A, 2],
        geo[G_A, 3],
        geo[G_X, 0],
        geo[G_X, 1],
        geo[G_X, 2],
        geo[G_X, 3],
        geo[G_Y, 0],
        geo[G_Y, 1],
        geo[G_Y, 2],
        geo[G_Y, 3],
        p[P_R],
        p[P_VMIN],
        p[P_KQ],
        p[P_NF],
        p[P_K],
        p[P_QMAX],
        p[P_KPSI],
        p[P_KR],
        p[P_DMAX],
        1.0 / p[P_IZ],
        1.0 / p[P_J],
        1.0 / p[P_TAU],
        1.0 / p[P_STAU],
        p[P_DRIVER],
        p[P_SELECT_LOW],
        p[P_ROAD],
        p[P_XJUMP],
        p[P_SPLIT_ROAD],
        p[P_YSPLIT],
        p[P_VSTOP],
        p[P_LOCK],
        p[P_HOPELESS],
        p[P_WINDOW],
        dt,
        0.5 * dt,
        dt / 6.0,
        float(n_steps),
        n_steps * dt,
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _surfaces(surfs):
    """The road's two surfaces as the lanes read them (`_surface_of`): (S_T, rise, fall0,
    fall1, target) of surface 0, then of surface 1."""
    return (
        surfs[0, SF_ST],
        surfs[0, SF_RISE],
        surfs[0, SF_FALL0],
        surfs[0, SF_FALL1],
        surfs[0, SF_TARGET],
        surfs[1, SF_ST],
        surfs[1, SF_RISE],
        surfs[1, SF_FALL0],
        surfs[1, SF_FALL1],
        surfs[1, SF_TARGET],
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wheel_kinematics(uw, vw, w, r_w, vmin):
    """(sx, v/|V|, |V|, clipped slip) of a wheel with wheel-frame velocity (uw, vw)."""
    vabs = fmax(math.sqrt(uw * uw + vw * vw), vmin)
    inv = 1.0 / vabs
    sx = (uw - w * r_w) * inv
    return sx, vw * inv, vabs, clip(sx, 0.0, 1.0)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _kinematics(vx, vy, r, delta, w, p, geo, sc):
    """Wheel-frame slips of the four wheels into the scratch rows (front wheels steered)."""
    if delta != 0.0:
        cd = math.cos(delta)
        sd = math.sin(delta)
    else:
        cd = 1.0
        sd = 0.0
    for j in range(4):
        u = vx - r * geo[G_Y, j]
        v = vy + r * geo[G_X, j]
        if j < 2 and sd != 0.0:
            uw = cd * u + sd * v
            vw = cd * v - sd * u
            sc[W_CS, j] = cd
            sc[W_SN, j] = sd
        else:
            uw = u
            vw = v
            sc[W_CS, j] = 1.0
            sc[W_SN, j] = 0.0
        sx, vr, vabs, slip = _wheel_kinematics(uw, vw, w[j], p[P_R], p[P_VMIN])
        sc[W_SX, j] = sx
        sc[W_VR, j] = vr
        sc[W_VABS, j] = vabs
        sc[W_SLIP, j] = slip


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _select_low(sc, select_low):
    """Rear channels on the larger-slip wheel's error (select-low), fronts individual."""
    if select_low and sc[W_E, 3] < sc[W_E, 2]:
        sc[W_E, 2] = sc[W_E, 3]
    elif select_low:
        sc[W_E, 3] = sc[W_E, 2]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wheel_rates(w, q, qr, z, xf, e, fxw, kp, ki, kd, u0, r_w, kq, inv_j, nf, gain, inv_tau, q_max):
    """Rates (dw, dq, dqr, dz, dxf) of a wheel's spin, brake actuator and PID states (DESIGN
    3.1, 4): J dw/dt = -R Fx - kq q (held at w = 0), T dqr/dt = K u - qr, dq/dt = qr held in
    [0, q_max], u = u0 + kp e + ki z + kd N (e - xf) with conditional integration. Branch-free."""
    dw = (-r_w * fxw - kq * q) * inv_j
    q_hi = q >= q_max
    q_lo = q <= 0.0
    u, dz, dxf = pid_step(e, z, xf, u0, kp, ki, kd, nf, q_hi, q_lo)
    return (
        select((w <= 0.0) & (dw < 0.0), 0.0, dw),
        select((q_hi & (qr > 0.0)) | (q_lo & (qr < 0.0)), 0.0, qr),
        (gain * u - qr) * inv_tau,
        dz,
        dxf,
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rhs(y, dy, i, law, sidx, guess, p, geo, surfs, sc, wbuf, tgt, inv):
    """Derivatives of candidate i's state `y` into dy[:, i]; returns the load-solve iterations.

    guess[:, i] holds the last (ax, ay) of the candidate (start of the load iteration), updated;
    inv = (1/Iz, 1/J, 1/T, 1/tau_steer).
    """
    vx = y[S_VX]
    vy = y[S_VY]
    r = y[S_YR]
    psi = y[S_PSI]
    delta = y[S_DELTA]
    for j in range(4):
        wbuf[j] = y[S_W + j]
    _kinematics(vx, vy, r, delta, wbuf, p, geo, sc)
    for j in range(4):
        tgt[j] = surfs[sidx[j, i], SF_TARGET]
    ax, ay, it = solve_loads(sc, surfs, sidx, i, geo, p[P_MASS], guess[0, i], guess[1, i])
    guess[0, i] = ax
    guess[1, i] = ay
    mz = 0.0
    for j in range(4):
        mz += geo[G_X, j] * sc[W_FYB, j] - geo[G_Y, j] * sc[W_FXB, j]
    dy[S_VX, i] = ax + vy * r
    dy[S_VY, i] = ay - vx * r
    dy[S_YR, i] = mz * inv[0]
    if psi != 0.0:
        cp = math.cos(psi)
        sp = math.sin(psi)
        dy[S_X, i] = vx * cp - vy * sp
        dy[S_Y, i] = vx * sp + vy * cp
    else:
        dy[S_X, i] = vx
        dy[S_Y, i] = vy
    dy[S_PSI, i] = r
    if p[P_DRIVER] != 0.0:
        cmd = min(max(-p[P_KPSI] * psi - p[P_KR] * r, -p[P_DMAX]), p[P_DMAX])
        dy[S_DELTA, i] = (cmd - delta) * inv[3]
    else:
        dy[S_DELTA, i] = 0.0
    for j in range(4):
        sc[W_E, j] = tgt[j] - sc[W_SLIP, j]
    _select_low(sc, p[P_SELECT_LOW] != 0.0)
    for j in range(4):
        dw, dq, dqr, dz, dxf = _wheel_rates(
            y[S_W + j],
            y[S_Q + j],
            y[S_QR + j],
            y[S_Z + j],
            y[S_XF + j],
            sc[W_E, j],
            sc[W_FXW, j],
            law[LAW_KP, j, i],
            law[LAW_KI, j, i],
            law[LAW_KD, j, i],
            law[LAW_U0, j, i],
            p[P_R],
            p[P_KQ],
            inv[1],
            p[P_NF],
            p[P_K],
            inv[2],
            p[P_QMAX],
        )
        dy[S_W + j, i] = dw
        dy[S_Q + j, i] = dq
        dy[S_QR + j, i] = dqr
        dy[S_Z + j, i] = dz
        dy[S_XF + j, i] = dxf
    return it


# ------------------------------------------------------------------------------------------------
# the straight-line step of one lane, in registers (the body of the vector loop)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _surface_of(b, srf):
    """(S_T, rise, fall0, fall1, target) of the surface a wheel is on (b: 1.0 the second)."""
    two = b != 0.0
    return (
        select(two, srf[5], srf[0]),
        select(two, srf[6], srf[1]),
        select(two, srf[7], srf[2]),
        select(two, srf[8], srf[3]),
        select(two, srf[9], srf[4]),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _straight_wheel(vx, w, s, r_w, vmin):
    """Force per unit load and clipped slip of a wheel on surface s in straight-line braking
    (r = vy = 0, no steering): `_kinematics` and `straight_force_per_load` in that case, bit for
    bit."""
    vabs = fmax(math.sqrt(vx * vx), vmin)
    sx = (vx - w * r_w) * (1.0 / vabs)
    a = abs(sx)
    sc = fmin(a, 1.0)
    mu = select(sc <= s[0], s[1] * sc, s[2] - s[3] * sc)
    return select(a > 0.0, -math.copysign(mu, sx), 0.0), clip(sx, 0.0, 1.0)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _lane_wheel_rates(wt, e, fx, g, kc):
    """`_wheel_rates` of wheel state wt = (w, q, qr, z, xf) with law g = (kp, ki, kd, u0)."""
    return _wheel_rates(
        wt[0],
        wt[1],
        wt[2],
        wt[3],
        wt[4],
        e,
        fx,
        g[0],
        g[1],
        g[2],
        g[3],
        kc[KC_RW],
        kc[KC_KQ],
        kc[KC_INV_J],
        kc[KC_NF],
        kc[KC_GAIN],
        kc[KC_INV_TAU],
        kc[KC_QMAX],
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _straight_stage(x, g, s, kc):
    """Derivatives at state x = (b, w0, w1, w2, w3), body b = (vx, vy, r, X, Y, psi, delta) and
    wheels wj = (w, q, qr, z, xf), with laws g and surfaces s (per wheel) in the straight-line
    case (no yaw, lateral velocity, heading or steering; loads in closed form): ((body rates,
    four wheel rates), ok), ok false where the case does not hold (`_rhs` then applies). The
    same formulas in the same order as `_rhs` and `solve_loads`."""
    b, w0, w1, w2, w3 = x
    g0, g1, g2, g3 = g
    s0, s1, s2, s3 = s
    vx = b[0]
    vy = b[1]
    r = b[2]
    psi = b[5]
    delta = b[6]
    r_w = kc[KC_RW]
    vmin = kc[KC_VMIN]
    c0, sl0 = _straight_wheel(vx, w0[0], s0, r_w, vmin)
    c1, sl1 = _straight_wheel(vx, w1[0], s1, r_w, vmin)
    c2, sl2 = _straight_wheel(vx, w2[0], s2, r_w, vmin)
    c3, sl3 = _straight_wheel(vx, w3[0], s3, r_w, vmin)
    num = 0.0
    num += c0 * kc[KC_FZ0]
    num += c1 * kc[KC_FZ0 + 1]
    num += c2 * kc[KC_FZ0 + 2]
    num += c3 * kc[KC_FZ0 + 3]
    mass = kc[KC_MASS]
    den = mass
    den -= c0 * kc[KC_A]
    den -= c1 * kc[KC_A + 1]
    den -= c2 * kc[KC_A + 2]
    den -= c3 * kc[KC_A + 3]
    ax = num / den
    fz0 = kc[KC_FZ0] + kc[KC_A] * ax
    fz1 = kc[KC_FZ0 + 1] + kc[KC_A + 1] * ax
    fz2 = kc[KC_FZ0 + 2] + kc[KC_A + 2] * ax
    fz3 = kc[KC_FZ0 + 3] + kc[KC_A + 3] * ax
    ok = (
        (vy == 0.0)
        & (r == 0.0)
        & (psi == 0.0)
        & (delta == 0.0)
        & (fz0 >= 0.0)
        & (fz1 >= 0.0)
        & (fz2 >= 0.0)
        & (fz3 >= 0.0)
    )
    fx0 = c0 * fz0
    fx1 = c1 * fz1
    fx2 = c2 * fz2
    fx3 = c3 * fz3
    total = 0.0
    total += fx0
    total += fx1
    total += fx2
    total += fx3
    ax = total / mass
    mz = 0.0
    mz += kc[KC_GX] * 0.0 - kc[KC_GY] * fx0
    mz += kc[KC_GX + 1] * 0.0 - kc[KC_GY + 1] * fx1
    mz += kc[KC_GX + 2] * 0.0 - kc[KC_GY + 2] * fx2
    mz += kc[KC_GX + 3] * 0.0 - kc[KC_GY + 3] * fx3
    dmax = kc[KC_DMAX]
    cmd = clip(-kc[KC_KPSI] * psi - kc[KC_KR] * r, -dmax, dmax)
    db = (
        ax + vy * r,
        0.0 - vx * r,
        mz * kc[KC_INV_IZ],
        vx,
        vy,
        r,
        select(kc[KC_DRIVER] != 0.0, (cmd - delta) * kc[KC_INV_ST], 0.0),
    )
    e0 = s0[4] - sl0
    e1 = s1[4] - sl1
    e2 = s2[4] - sl2
    e3 = s3[4] - sl3
    sel = kc[KC_SELECT_LOW] != 0.0
    low = e3 < e2
    high = not low
    return (
        db,
        _lane_wheel_rates(w0, e0, fx0, g0, kc),
        _lane_wheel_rates(w1, e1, fx1, g1, kc),
        _lane_wheel_rates(w2, select(sel & low, e3, e2), fx2, g2, kc),
        _lane_wheel_rates(w3, select(sel & high, e2, e3), fx3, g3, kc),
    ), ok


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _held(x, q_max):
    """The state x after the step-end limits: each wheel's w held >= 0 and q in [0, q_max]."""
    b, w0, w1, w2, w3 = x
    return (
        b,
        (fmax(w0[0], 0.0), clip(w0[1], 0.0, q_max), w0[2], w0[3], w0[4]),
        (fmax(w1[0], 0.0), clip(w1[1], 0.0, q_max), w1[2], w1[3], w1[4]),
        (fmax(w2[0], 0.0), clip(w2[1], 0.0, q_max), w2[2], w2[3], w2[4]),
        (fmax(w3[0], 0.0), clip(w3[1], 0.0, q_max), w3[2], w3[3], w3[4]),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _get(st, row, l):
    return st[row * LANES + l]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _put(st, row, l, commit, value):
    """Row `row` of lane l becomes `value` where `commit` (else it keeps its value)."""
    st[row * LANES + l] = select(commit, value, st[row * LANES + l])


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _state(a, row0, stride, l):
    """The state as tuples (body, wheel fl, fr, rl, rr), state row s at a[(row0 + s) stride + l]:
    the rows of lane l in `st` (stride LANES) or a state vector (stride 1, l = 0)."""
    return (
        (
            a[(row0 + S_VX) * stride + l],
            a[(row0 + S_VY) * stride + l],
            a[(row0 + S_YR) * stride + l],
            a[(row0 + S_X) * stride + l],
            a[(row0 + S_Y) * stride + l],
            a[(row0 + S_PSI) * stride + l],
            a[(row0 + S_DELTA) * stride + l],
        ),
        _wheel(a, row0, stride, 0, l),
        _wheel(a, row0, stride, 1, l),
        _wheel(a, row0, stride, 2, l),
        _wheel(a, row0, stride, 3, l),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wheel(a, row0, stride, j, l):
    """Wheel j's (w, q, qr, z, xf) in the rows of `_state`."""
    return (
        a[(row0 + S_W + j) * stride + l],
        a[(row0 + S_Q + j) * stride + l],
        a[(row0 + S_QR + j) * stride + l],
        a[(row0 + S_Z + j) * stride + l],
        a[(row0 + S_XF + j) * stride + l],
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _law(st, j, l):
    return (
        _get(st, R_KP + j, l),
        _get(st, R_KI + j, l),
        _get(st, R_KD + j, l),
        _get(st, R_U0 + j, l),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _put_state(st, row0, l, commit, x):
    """`_state` rows of lane l become x = (body, wheels) where `commit`."""
    b = x[0]
    _put(st, row0 + S_VX, l, commit, b[0])
    _put(st, row0 + S_VY, l, commit, b[1])
    _put(st, row0 + S_YR, l, commit, b[2])
    _put(st, row0 + S_X, l, commit, b[3])
    _put(st, row0 + S_Y, l, commit, b[4])
    _put(st, row0 + S_PSI, l, commit, b[5])
    _put(st, row0 + S_DELTA, l, commit, b[6])
    _put_wheel(st, row0, 0, l, commit, x[1])
    _put_wheel(st, row0, 1, l, commit, x[2])
    _put_wheel(st, row0, 2, l, commit, x[3])
    _put_wheel(st, row0, 3, l, commit, x[4])


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _put_wheel(st, row0, j, l, commit, w):
    _put(st, row0 + S_W + j, l, commit, w[0])
    _put(st, row0 + S_Q + j, l, commit, w[1])
    _put(st, row0 + S_QR + j, l, commit, w[2])
    _put(st, row0 + S_Z + j, l, commit, w[3])
    _put(st, row0 + S_XF + j, l, commit, w[4])


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _laws_surfaces(st, l, srf):
    """Lane l's wheel laws ((kp, ki, kd, u0) per wheel) and the surfaces under its wheels."""
    return (
        (_law(st, 0, l), _law(st, 1, l), _law(st, 2, l), _law(st, 3, l)),
        (
            _surface_of(_get(st, R_SURF, l), srf),
            _surface_of(_get(st, R_SURF + 1, l), srf),
            _surface_of(_get(st, R_SURF + 2, l), srf),
            _surface_of(_get(st, R_SURF + 3, l), srf),
        ),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _target(st, j, l, srf):
    """Target slip of the surface under wheel j of lane l."""
    return _surface_of(_get(st, R_SURF + j, l), srf)[4]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _surface_flag(b_old, x, y, cp, sp, j, kc):
    """Surface under wheel j (1.0: the second) from its contact point's global position on
    mu-jump and split-mu roads (kept on uniform roads), heading psi given as (cos, sin)."""
    gx = x + kc[KC_GX + j] * cp - kc[KC_GY + j] * sp
    gy = y + kc[KC_GX + j] * sp + kc[KC_GY + j] * cp
    split = select(
        kc[KC_SPLIT_ROAD] != 0.0,
        select(gy >= kc[KC_YSPLIT], 0.0, 1.0),
        select(kc[KC_GY + j] > 0.0, 0.0, 1.0),
    )
    return select(
        kc[KC_KIND] == ROAD_MU_JUMP,
        select(gx >= kc[KC_XJUMP], 1.0, 0.0),
        select(kc[KC_KIND] == ROAD_SPLIT, split, b_old),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _put_surface(st, l, commit, j, b, cp, sp, kc):
    """The surface flag of wheel j of lane l at the body state b (`_surface_flag`)."""
    _put(
        st, R_SURF + j, l, commit, _surface_flag(_get(st, R_SURF + j, l), b[3], b[4], cp, sp, j, kc)
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wheel_end(st, l, commit, j, s_new, vabs, w, w0, vabs0, acc, timing, kc, srf):
    """Step-end integrals of wheel j (slip, its error to the target, locking), its slip at the
    step's end (at the stop when the run stops) and, in the step it first locks, that step's
    start and its margins w R - lock_ratio |V| at the start (w0, vabs0) and the end (the lock
    time: `_lock_time`). acc = (iae, itae, ise, locked, all still) so far, returned updated;
    timing = (t, the stop's crossing fraction, the step's length up to the stop, stop, moving)."""
    t, frac, h, stop, moving = timing
    slip = _get(st, R_SLIP + j, l)
    target = _target(st, j, l, srf)
    s_end = slip + frac * (s_new - slip)
    d_iae, d_itae, d_ise = error_integrals(target - slip, target - s_end, t, h)
    _put(st, R_SINT + j, l, commit, _get(st, R_SINT + j, l) + trapezoid(slip, s_end, h))
    _put(st, R_SLIP + j, l, commit, select(stop, s_end, s_new))
    locked = moving & (w * kc[KC_RW] < kc[KC_LOCK] * vabs)
    lock_t = _get(st, R_LOCK_T + j, l)
    first = locked & (lock_t != lock_t)
    _put(st, R_LOCK_T + j, l, commit, select(first, t, lock_t))
    _put(st, R_LOCK_M0 + j, l, commit & first, w0 * kc[KC_RW] - kc[KC_LOCK] * vabs0)
    _put(st, R_LOCK_M1 + j, l, commit & first, w * kc[KC_RW] - kc[KC_LOCK] * vabs)
    return (
        acc[0] + d_iae,
        acc[1] + d_itae,
        acc[2] + d_ise,
        acc[3] + select(locked, kc[KC_DT], 0.0),
        acc[4] & (w == 0.0),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _end_step(st, l, commit, x0, vabs0, x, slips, vabs, cp, sp, k4, kc, srf, stops):
    """Commit the step from state x0 (its wheels' |V|: vabs0) to state x = (b, w0, w1, w2, w3)
    and k4 of lane l where `commit`: distance, integrals, locking, surfaces, yaw metrics,
    status; at a stop the lane keeps the state at the stop (`_at_stop`) and the surfaces of the
    step. `stops`, a constant: whether this pass may commit the step in which the run stops
    (False folds the stop's code away). Returns whether the run ended."""
    b, w0, w1, w2, w3 = x
    dt = kc[KC_DT]
    v_stop = kc[KC_VSTOP]
    k = _get(st, R_STEP, l)
    t = k * dt
    vx = b[0]
    vy = b[1]
    sp_new = math.sqrt(vx * vx + vy * vy)
    sp_old = _get(st, R_SPEED, l)
    stop = (sp_new <= v_stop) & stops  # a constant False folds the stop away
    frac = crossing_fraction(sp_old, sp_new, v_stop, stop)
    h = frac * dt
    dist = _get(st, R_DIST, l) + trapezoid(sp_old, select(stop, v_stop, sp_new), h)
    moving = sp_new > v_stop
    acc = (_get(st, R_IAE, l), _get(st, R_ITAE, l), _get(st, R_ISE, l), _get(st, R_LOCKED, l), True)
    timing = (t, frac, h, stop, moving)
    acc = _wheel_end(
        st, l, commit, 0, slips[0], vabs[0], w0[0], x0[1][0], vabs0[0], acc, timing, kc, srf
    )
    acc = _wheel_end(
        st, l, commit, 1, slips[1], vabs[1], w1[0], x0[2][0], vabs0[1], acc, timing, kc, srf
    )
    acc = _wheel_end(
        st, l, commit, 2, slips[2], vabs[2], w2[0], x0[3][0], vabs0[2], acc, timing, kc, srf
    )
    acc = _wheel_end(
        st, l, commit, 3, slips[3], vabs[3], w3[0], x0[4][0], vabs0[3], acc, timing, kc, srf
    )
    iae, itae, ise, locked, all_still = acc
    all_t = _get(st, R_ALL_T, l)
    first = all_still & (all_t != all_t) & moving
    _put(st, R_ALL_T, l, commit, select(first, t + dt, all_t))
    _put(st, R_ALL_V, l, commit, select(first, sp_new, _get(st, R_ALL_V, l)))
    _put(st, R_ALL_D, l, commit, select(first, dist, _get(st, R_ALL_D, l)))
    switch = commit & (not stop)
    _put_surface(st, l, switch, 0, b, cp, sp, kc)
    _put_surface(st, l, switch, 1, b, cp, sp, kc)
    _put_surface(st, l, switch, 2, b, cp, sp, kc)
    _put_surface(st, l, switch, 3, b, cp, sp, kc)
    r_now = b[2]
    psi_now = b[5]
    in_window = t + 0.5 * dt < kc[KC_WINDOW]
    yaw_pk1 = _get(st, R_YAWPK1, l)
    _put(st, R_YAWPK1, l, commit, select(in_window & (abs(r_now) > abs(yaw_pk1)), r_now, yaw_pk1))
    window_end = in_window & (t + 1.5 * dt >= kc[KC_WINDOW])
    _put(st, R_PSI1, l, commit, select(window_end, psi_now, _get(st, R_PSI1, l)))
    _put(st, R_Y1, l, commit, select(window_end, b[4], _get(st, R_Y1, l)))
    spin_t = _get(st, R_SPIN_T, l)
    no_spin = spin_t != spin_t
    yaw_pk = _get(st, R_YAWPK, l)
    _put(st, R_YAWPK, l, commit, select(no_spin & (abs(r_now) > abs(yaw_pk)), r_now, yaw_pk))
    _put(st, R_SPIN_T, l, commit, select(no_spin & (abs(psi_now) >= 0.5 * math.pi), t + dt, spin_t))
    check = sp_new + r_now + psi_now + itae + w0[1] + w0[3] + w0[0]
    diverged = check - check != 0.0
    hopeless = dist > kc[KC_HOPELESS]
    timeout = k + 1.0 >= kc[KC_NSTEPS]
    _put(
        st,
        R_STATUS,
        l,
        commit,
        select(
            diverged,
            STATUS_DIVERGED,
            select(stop, STATUS_STOPPED, select(hopeless, STATUS_HOPELESS, STATUS_TIMEOUT)),
        ),
    )
    _put(
        st,
        R_TEND,
        l,
        commit,
        select(diverged, t, select(stop, t + h, select(hopeless, t + dt, kc[KC_TTIMEOUT]))),
    )
    ended = diverged | stop | hopeless | timeout
    _put(st, R_ENDED, l, commit, select(ended, 1.0, 0.0))
    _put(st, R_SPEED, l, commit, sp_new)
    _put(st, R_DIST, l, commit, dist)
    _put(st, R_IAE, l, commit, iae)
    _put(st, R_ITAE, l, commit, itae)
    _put(st, R_ISE, l, commit, ise)
    _put(st, R_LOCKED, l, commit, locked)
    _put(st, R_STEP, l, commit, k + 1.0)
    _put_state(st, 0, l, commit, _at_stop(x0, x, stop, 1.0 - frac, dt, cp, sp))
    _put_state(st, R_K4, l, commit, k4)
    return ended


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _rate_at_stop(a, b, stop, back):
    """b, or at a stop the value linear from a (step start) to b (end) a fraction `back` of the
    step before its end: the crossing fraction of the speed, linear over the step."""
    return select(stop, b - back * (b - a), b)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _integral_at_stop(a, b, rate_b, stop, back, dt):
    """b, or at a stop the integral of a rate linear over the step (a position under the
    speed's linear law): the parabola through a (step start) and b with the slope rate_b at
    the end, `back` of the step before it: b - back dt rate_b + back^2 (a - b + dt rate_b)."""
    return select(stop, b - back * dt * rate_b + back * back * (a - b + dt * rate_b), b)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wheel_at_stop(a, b, stop, back):
    return (
        _rate_at_stop(a[0], b[0], stop, back),
        _rate_at_stop(a[1], b[1], stop, back),
        _rate_at_stop(a[2], b[2], stop, back),
        _rate_at_stop(a[3], b[3], stop, back),
        _rate_at_stop(a[4], b[4], stop, back),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _at_stop(x0, x, stop, back, dt, cp, sp):
    """The state x, or at a stop the state at the stop instant, `back` of the step before x
    (x0 the step's start): the speeds, wheel and controller states linear over the step as
    the stop's crossing assumes, X, Y and the heading their integrals (`_integral_at_stop`,
    slopes the end's global velocity from the heading's (cos, sin) = (cp, sp) and the yaw
    rate)."""
    a, b = x0[0], x[0]
    vx, vy, r = b[0], b[1], b[2]
    body = (
        _rate_at_stop(a[0], vx, stop, back),
        _rate_at_stop(a[1], vy, stop, back),
        _rate_at_stop(a[2], r, stop, back),
        _integral_at_stop(a[3], b[3], vx * cp - vy * sp, stop, back, dt),
        _integral_at_stop(a[4], b[4], vx * sp + vy * cp, stop, back, dt),
        _integral_at_stop(a[5], b[5], r, stop, back, dt),
        _rate_at_stop(a[6], b[6], stop, back),
    )
    return (
        body,
        _wheel_at_stop(x0[1], x[1], stop, back),
        _wheel_at_stop(x0[2], x[2], stop, back),
        _wheel_at_stop(x0[3], x[3], stop, back),
        _wheel_at_stop(x0[4], x[4], stop, back),
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _unsteered(b, wt, j, kc):
    """(|V|, clipped slip) of wheel j (state wt) unsteered, body b: `_kinematics` with delta 0."""
    vx = b[0]
    vy = b[1]
    r = b[2]
    u = vx - r * kc[KC_GY + j]
    _, _, vabs, slip = _wheel_kinematics(u, vy + r * kc[KC_GX + j], wt[0], kc[KC_RW], kc[KC_VMIN])
    return vabs, slip


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wheel_speeds(x, kc):
    """The four wheels' |V| at state x (unsteered: steering turns a wheel's velocity, not its
    norm)."""
    b = x[0]
    return (
        _unsteered(b, x[1], 0, kc)[0],
        _unsteered(b, x[2], 1, kc)[0],
        _unsteered(b, x[3], 2, kc)[0],
        _unsteered(b, x[4], 3, kc)[0],
    )


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _lane_step(st, l, kc, srf, live):
    """One RK4 step of lane l in the straight-line case, committed (R_DONE 1) only if every
    stage and the step's end are straight and the run does not stop in it (that step, once a
    run, is the scalar pass's: it locates the stop); returns 1 if a live lane ended.
    Straight-line code: the body of the vector loop."""
    x = _state(st, 0, LANES, l)
    g, s = _laws_surfaces(st, l, srf)
    hs = kc[KC_HS]
    dt = kc[KC_DT]
    ka, ok1 = _straight_stage(rk4_point(x, 0.0, _state(st, R_K4, LANES, l)), g, s, kc)
    kb, ok2 = _straight_stage(rk4_point(x, hs, ka), g, s, kc)
    kc3, ok3 = _straight_stage(rk4_point(x, hs, kb), g, s, kc)
    kd, ok4 = _straight_stage(rk4_point(x, dt, kc3), g, s, kc)
    xn = _held(rk4_update(x, kc[KC_H6], ka, kb, kc3, kd), kc[KC_QMAX])
    nb, n0, n1, n2, n3 = xn
    straight = (
        ok1 & ok2 & ok3 & ok4 & (nb[1] == 0.0) & (nb[2] == 0.0) & (nb[5] == 0.0) & (nb[6] == 0.0)
    )
    stopping = math.sqrt(nb[0] * nb[0] + nb[1] * nb[1]) <= kc[KC_VSTOP]
    commit = straight & (not stopping)
    # the step end's kinematics with delta = 0 (`_kinematics`, unsteered)
    va0, sl0 = _unsteered(nb, n0, 0, kc)
    va1, sl1 = _unsteered(nb, n1, 1, kc)
    va2, sl2 = _unsteered(nb, n2, 2, kc)
    va3, sl3 = _unsteered(nb, n3, 3, kc)
    v0 = fmax(abs(x[0][0]), kc[KC_VMIN])  # every wheel's |V| at the straight start
    ended = _end_step(
        st,
        l,
        commit,
        x,
        (v0, v0, v0, v0),
        xn,
        (sl0, sl1, sl2, sl3),
        (va0, va1, va2, va3),
        1.0,
        0.0,
        kd,
        kc,
        srf,
        False,
    )
    st[R_DONE * LANES + l] = select(commit, 1.0, 0.0)
    return ended & commit & (l < live)


@numba.njit(**_NO_REFCOUNT)
def _lane_steps(st, width, kc, srf, live):
    """One step of lanes 0 .. width - 1 (a whole number of vectors); 1 if a live lane ended."""
    any_end = False
    for blk in range(width // VECTOR):
        for j in range(VECTOR):
            any_end |= _lane_step(st, blk * VECTOR + j, kc, srf, live)
    return any_end


# ------------------------------------------------------------------------------------------------
# scalar passes: the general step, a sampled controller's tick, filling and finishing lanes


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _lane_arrays(st, l, law, sidx, guess):
    """Lane l's wheel laws, surfaces and load guess as the arrays `_rhs` reads (column 0)."""
    for j in range(4):
        law[LAW_KP, j, 0] = _get(st, R_KP + j, l)
        law[LAW_KI, j, 0] = _get(st, R_KI + j, l)
        law[LAW_KD, j, 0] = _get(st, R_KD + j, l)
        law[LAW_U0, j, 0] = _get(st, R_U0 + j, l)
        sidx[j, 0] = 1 if _get(st, R_SURF + j, l) != 0.0 else 0
    guess[0, 0] = _get(st, R_AX, l)
    guess[1, 0] = _get(st, R_AY, l)


@numba.njit(**_NO_REFCOUNT)
def _general_step(
    st, l, kc, srf, p, geo, surfs, x, ks, y, dy, law, sidx, guess, sc, wbuf, tgt, inv
):
    """The step of lane l stage by stage: each stage in the straight-line case where it holds,
    else the general right-hand side `_rhs` (loads by Newton's method from the lane's last
    general solution). Returns whether the run ended."""
    for s in range(N_STATE):
        x[s] = _get(st, s, l)
        ks[3, s] = _get(st, R_K4 + s, l)  # stage 1 reads the last step's k4
    _lane_arrays(st, l, law, sidx, guess)
    g, srfs = _laws_surfaces(st, l, srf)
    iters = _get(st, R_ITER, l)
    for stage in range(4):
        c = 0.0 if stage == 0 else (kc[KC_DT] if stage == 3 else kc[KC_HS])
        prev = 3 if stage == 0 else stage - 1
        for s in range(N_STATE):
            y[s] = rk4_point(x[s], c, ks[prev, s])
        (kb, k0, k1, k2, k3), ok = _straight_stage(_state(y, 0, 1, 0), g, srfs, kc)
        if ok:
            for s in range(7):
                ks[stage, s] = kb[s]
            for j, kw in enumerate((k0, k1, k2, k3)):
                ks[stage, S_W + j] = kw[0]
                ks[stage, S_Q + j] = kw[1]
                ks[stage, S_QR + j] = kw[2]
                ks[stage, S_Z + j] = kw[3]
                ks[stage, S_XF + j] = kw[4]
        else:
            it = _rhs(y, dy, 0, law, sidx, guess, p, geo, surfs, sc, wbuf, tgt, inv)
            iters = max(iters, it)
            for s in range(N_STATE):
                ks[stage, s] = dy[s, 0]
    h6 = kc[KC_H6]
    for s in range(N_STATE):
        y[s] = rk4_update(x[s], h6, ks[0, s], ks[1, s], ks[2, s], ks[3, s])
    for j in range(4):
        y[S_W + j] = max(y[S_W + j], 0.0)
        y[S_Q + j] = min(max(y[S_Q + j], 0.0), kc[KC_QMAX])
        wbuf[j] = y[S_W + j]
    _kinematics(y[S_VX], y[S_VY], y[S_YR], y[S_DELTA], wbuf, p, geo, sc)
    psi = y[S_PSI]
    cp = math.cos(psi) if psi != 0.0 else 1.0
    sp = math.sin(psi) if psi != 0.0 else 0.0
    x0 = _state(x, 0, 1, 0)
    ended = _end_step(
        st,
        l,
        True,
        x0,
        _wheel_speeds(x0, kc),
        _state(y, 0, 1, 0),
        (sc[W_SLIP, 0], sc[W_SLIP, 1], sc[W_SLIP, 2], sc[W_SLIP, 3]),
        (sc[W_VABS, 0], sc[W_VABS, 1], sc[W_VABS, 2], sc[W_VABS, 3]),
        cp,
        sp,
        _state(ks[3], 0, 1, 0),
        kc,
        srf,
        True,
    )
    st[R_AX * LANES + l] = guess[0, 0]
    st[R_AY * LANES + l] = guess[1, 0]
    st[R_ITER * LANES + l] = iters
    return ended


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _channel_errors(e0, e1, e2, e3, select_low):
    """The four channels' slip errors: select-low gives both rear channels min(e2, e3)."""
    if select_low and e3 < e2:
        return e0, e1, e3, e3
    if select_low:
        return e0, e1, e2, e2
    return e0, e1, e2, e3


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _tick_wheel(st, l, i, k, j, src, e, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts):
    """Wheel j's part of `_tick`: the law's tick (`law_tick`) on its channel error e, with the
    signals of wheel src (itself, or under select-low the rear wheel whose error it took)."""
    sig = (
        e,
        _get(st, R_SLIP + src, l),
        _target(st, src, l, srf),
        _get(st, S_W + src, l),
        _get(st, R_WS + src, l),
        kc[KC_RW],
        kc[KC_NF] * (e - _get(st, S_XF + j, l)),
    )
    held = (
        _get(st, R_U0 + j, l),
        _get(st, R_KP + j, l),
        _get(st, R_KI + j, l),
        _get(st, R_KD + j, l),
    )
    mem = (_get(st, R_MEM + j, l), _get(st, R_MEM + 4 + j, l))
    (u0, kp, ki, kd), (m0, m1) = law_tick(
        laws_key, ctrl_kind, sig, held, mem, gains[i], col0[j], c, table, ts, k == 0
    )
    st[(R_U0 + j) * LANES + l] = u0
    st[(R_KP + j) * LANES + l] = kp
    st[(R_KI + j) * LANES + l] = ki
    st[(R_KD + j) * LANES + l] = kd
    st[(R_MEM + j) * LANES + l] = m0
    st[(R_MEM + 4 + j) * LANES + l] = m1


@numba.njit(**_NO_REFCOUNT)
def _tick(st, l, i, k, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts):
    """A sampled law's update of lane l (candidate i) at its step k, a sample instant (the law
    dispatch compiles for `laws_key`, a literal)."""
    sel = kc[KC_SELECT_LOW] != 0.0
    err0 = _target(st, 0, l, srf) - _get(st, R_SLIP, l)
    err1 = _target(st, 1, l, srf) - _get(st, R_SLIP + 1, l)
    err2 = _target(st, 2, l, srf) - _get(st, R_SLIP + 2, l)
    err3 = _target(st, 3, l, srf) - _get(st, R_SLIP + 3, l)
    e0, e1, e2, e3 = _channel_errors(err0, err1, err2, err3, sel)
    rear = 3 if (sel and err3 < err2) else 2  # select-low: the rear wheel whose error it took
    _tick_wheel(st, l, i, k, 0, 0, e0, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
    _tick_wheel(st, l, i, k, 1, 1, e1, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
    src2, src3 = (rear, rear) if sel else (2, 3)
    _tick_wheel(st, l, i, k, 2, src2, e2, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
    _tick_wheel(st, l, i, k, 3, src3, e3, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
    for j in range(4):
        st[(R_WS + j) * LANES + l] = _get(st, S_W + j, l)


@numba.njit(**_NO_REFCOUNT)
def _fill_lane(st, l, i, gains, col0, laws_key, ctrl_kind, c, kc, srf, v0):
    """Start candidate i in lane l: wheels rolling freely at v0, zero metrics, the law's held
    values at the start (`Law.forms`: the PID's gains, the driver's command without ABS), the
    surfaces under the wheels at t = 0 and the derivative filters at e(0) (no kick; the law
    dispatch compiles for `laws_key`, a literal)."""
    for row in range(N_ROWS):
        st[row * LANES + l] = 0.0
    st[S_VX * LANES + l] = v0
    for j in range(4):
        st[(S_W + j) * LANES + l] = v0 / kc[KC_RW]
        st[(R_WS + j) * LANES + l] = v0 / kc[KC_RW]
        st[(R_LOCK_T + j) * LANES + l] = np.nan
        u0, kp, ki, kd = law_start(laws_key, ctrl_kind, gains[i], col0[j], c)
        st[(R_U0 + j) * LANES + l] = u0
        st[(R_KP + j) * LANES + l] = kp
        st[(R_KI + j) * LANES + l] = ki
        st[(R_KD + j) * LANES + l] = kd
        st[(R_SURF + j) * LANES + l] = _surface_flag(0.0, 0.0, 0.0, 1.0, 0.0, j, kc)
    # e(0): the wheels roll freely
    e = _channel_errors(
        _target(st, 0, l, srf),
        _target(st, 1, l, srf),
        _target(st, 2, l, srf),
        _target(st, 3, l, srf),
        kc[KC_SELECT_LOW] != 0.0,
    )
    for j in range(4):
        st[(S_XF + j) * LANES + l] = e[j]
    st[R_SPEED * LANES + l] = v0
    for row in (R_ALL_T, R_ALL_V, R_ALL_D, R_PSI1, R_Y1, R_SPIN_T):
        st[row * LANES + l] = np.nan
    st[R_STATUS * LANES + l] = STATUS_TIMEOUT
    st[R_TEND * LANES + l] = kc[KC_TTIMEOUT]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _lock_time(st, j, l, dt):
    """Wheel j's lock time (NaN: never): where its margin w R - lock_ratio |V|, linear over the
    step in which it first locked, crosses 0."""
    t = _get(st, R_LOCK_T + j, l)
    m0 = _get(st, R_LOCK_M0 + j, l)
    frac = crossing_fraction(m0, _get(st, R_LOCK_M1 + j, l), 0.0, True)
    return select(t == t, t + frac * dt, t)


@numba.njit(**_NO_REFCOUNT)
def _finish_lane(st, l, out_row, dt):
    """Write the metrics row of the run that ended in lane l (step dt)."""
    t_end = _get(st, R_TEND, l)
    psi1 = _get(st, R_PSI1, l)
    y1 = _get(st, R_Y1, l)
    spin_t = _get(st, R_SPIN_T, l)
    out_row[:] = 0.0
    out_row[M_STATUS] = _get(st, R_STATUS, l)
    out_row[M_TIME] = t_end
    out_row[M_DIST] = _get(st, R_DIST, l)
    out_row[M_XSTOP] = _get(st, S_X, l)
    out_row[M_IAE] = _get(st, R_IAE, l)
    out_row[M_ITAE] = _get(st, R_ITAE, l)
    out_row[M_ISE] = _get(st, R_ISE, l)
    out_row[M_LOCKED] = _get(st, R_LOCKED, l)
    out_row[M_YAWPK1] = _get(st, R_YAWPK1, l)
    out_row[M_PSI1] = math.degrees(psi1 if psi1 == psi1 else _get(st, S_PSI, l))
    out_row[M_Y1] = y1 if y1 == y1 else _get(st, S_Y, l)
    out_row[M_YAWPK] = _get(st, R_YAWPK, l)
    out_row[M_SPUN] = 0.0 if spin_t != spin_t else 1.0
    out_row[M_SPIN_T] = spin_t
    out_row[M_PSI_END] = math.degrees(_get(st, S_PSI, l))
    out_row[M_Y_END] = _get(st, S_Y, l)
    out_row[M_ALL_T] = _get(st, R_ALL_T, l)
    out_row[M_ALL_V] = _get(st, R_ALL_V, l)
    out_row[M_ALL_D] = _get(st, R_ALL_D, l)
    for j in range(4):
        out_row[M_MEAN_SLIP + j] = _get(st, R_SINT + j, l) / t_end if t_end > 0.0 else 0.0
        out_row[M_LOCK_T + j] = _lock_time(st, j, l, dt)
    out_row[M_ITER] = _get(st, R_ITER, l)


@numba.njit(**_NO_REFCOUNT)
def _simulate(laws_key, gains, p, geo, surfs, ctrl_kind, c, table, trace, out, scratch):
    """Simulate every row of `gains` (n, G): the wheel law's gains in catalogue order, twice
    (front, then rear) when p[axle_gains] is 1.

    p: PLANT_LAYOUT vector; geo: GEOMETRY_LAYOUT rows x 4 wheels; surfs: surface rows (SF_*
    columns of `plants.abs_vehicle`), index 0 and 1; c: the single wheel's controller vector
    (ts_s, amplitude, thresholds); table: a compiled fuzzy surface (any surface for other laws).
    Writes each candidate's METRIC_LAYOUT row into out (n, N_METRICS); when `trace` has rows
    (n must be 1), also the TRACE_LAYOUT time series, one row per step. `scratch`: the arrays
    of `scratch()` (any contents: reset here; nothing is allocated).
    """
    x, ks, y, dy, law, sidx, guess, sc, wbuf, tgt, inv, st, lane_of, col0 = scratch
    n = gains.shape[0]
    kc = _constants(p, geo)
    srf = _surfaces(surfs)
    dt = kc[KC_DT]
    n_g = gains.shape[1] // 2 if p[P_AXLE] != 0.0 else gains.shape[1]
    col0[:] = 0  # first gain column of each wheel
    for j in range(2, 4):
        col0[j] = n_g if p[P_AXLE] != 0.0 else 0
    steps_per_sample = max(1, round(c[Q_TS] / dt))
    ts = steps_per_sample * dt
    sampled = law_sampled(laws_key, ctrl_kind)
    # scratch of the scalar passes
    x[:] = 0.0
    ks[:] = 0.0
    y[:] = 0.0
    dy[:] = 0.0
    law[:] = 0.0
    sidx[:] = 0
    guess[:] = 0.0
    sc[:] = 0.0
    wbuf[:] = 0.0
    tgt[:] = 0.0
    inv[0] = kc[KC_INV_IZ]
    inv[1] = kc[KC_INV_J]
    inv[2] = kc[KC_INV_TAU]
    inv[3] = kc[KC_INV_ST]
    st[:] = 0.0
    lane_of[:] = -1  # candidate in each lane
    live = min(n, LANES)
    for l in range(live):
        _fill_lane(st, l, l, gains, col0, laws_key, ctrl_kind, c, kc, srf, p[P_V0])
        lane_of[l] = l
    queued = live  # next candidate to start
    n_trace = trace.shape[0]
    rows = 0
    if n_trace > 0 and n > 0:
        _trace_row(
            trace[rows],
            rows == 0,
            0.0,
            st,
            0,
            p,
            geo,
            surfs,
            law,
            sidx,
            guess,
            sc,
            y,
            dy,
            wbuf,
            tgt,
            inv,
        )
        rows = 1
    while live > 0:
        if sampled:  # at each lane's own sample instants
            for l in range(live):
                k = int(_get(st, R_STEP, l))
                if k % steps_per_sample == 0:
                    i = lane_of[l]
                    _tick(st, l, i, k, gains, col0, laws_key, ctrl_kind, c, table, kc, srf, ts)
        width = -(-live // VECTOR) * VECTOR
        ended = _lane_steps(st, width, kc, srf, live)
        for l in range(live):
            if _get(st, R_DONE, l) == 0.0:
                ended |= _general_step(
                    st,
                    l,
                    kc,
                    srf,
                    p,
                    geo,
                    surfs,
                    x,
                    ks,
                    y,
                    dy,
                    law,
                    sidx,
                    guess,
                    sc,
                    wbuf,
                    tgt,
                    inv,
                )
        if n_trace > 0 and rows < n_trace:  # one candidate, in lane 0
            t = (_get(st, R_STEP, 0) - 1.0) * dt
            _trace_row(
                trace[rows],
                rows == 0,
                min(t + dt, _get(st, R_TEND, 0)),
                st,
                0,
                p,
                geo,
                surfs,
                law,
                sidx,
                guess,
                sc,
                y,
                dy,
                wbuf,
                tgt,
                inv,
            )
            if _get(st, R_STATUS, 0) == STATUS_STOPPED:  # the row at the stop
                trace[rows, T_SPEED] = kc[KC_VSTOP]
            rows += 1
        if ended:
            for l in range(live - 1, -1, -1):  # high to low: lanes moved down are done
                if _get(st, R_ENDED, l) == 0.0:
                    continue
                i = lane_of[l]
                _finish_lane(st, l, out[i], dt)
                if queued < n:
                    _fill_lane(st, l, queued, gains, col0, laws_key, ctrl_kind, c, kc, srf, p[P_V0])
                    lane_of[l] = queued
                    queued += 1
                else:
                    live = close_lane(st, l, live, lane_of, N_ROWS, LANES)
    if n_trace > 0 and n > 0:
        out[0, M_NTRACE] = rows


def _entry_point(laws_key):
    """The cached entry point for the registered control laws named by `laws_key`
    (`controllers.laws.registry.fingerprint`, as an integer: a closure variable, on which numba
    keys the disk cache; the law dispatch is generated from the registry when it compiles)."""

    def simulate_abs_vehicle(gains, p, geo, surfs, ctrl_kind, c, table, trace, out, scratch):
        _simulate(laws_key, gains, p, geo, surfs, ctrl_kind, c, table, trace, out, scratch)

    simulate_abs_vehicle.__doc__ = _simulate.__doc__
    return numba.njit(**_NO_REFCOUNT)(simulate_abs_vehicle)


_ENTRY_POINTS: dict[str, Any] = {}


def entry_point() -> Any:
    """The compiled entry point for the laws registered now."""
    key = laws.fingerprint()
    if key not in _ENTRY_POINTS:
        _ENTRY_POINTS[key] = _entry_point(int(key[:15], 16))
    return _ENTRY_POINTS[key]


def simulate_abs_vehicle(
    gains: np.ndarray,
    p: np.ndarray,
    geo: np.ndarray,
    surfs: np.ndarray,
    ctrl_kind: int,
    c: np.ndarray,
    table: tuple[np.ndarray, ...],
    trace: np.ndarray,
    out: np.ndarray,
    scratch: tuple[np.ndarray, ...],
) -> None:
    """`_simulate` through the entry point of the registered laws (`entry_point`)."""
    entry_point()(gains, p, geo, surfs, ctrl_kind, c, table, trace, out, scratch)


@numba.njit(**_NO_REFCOUNT)
def _trace_row(
    trace_row, start, t, st, l, p, geo, surfs, law, sidx, guess, sc, y, dy, wbuf, tgt, inv
):
    """Trace row `trace_row` of lane l: its state, and loads and forces re-evaluated at it (`_rhs`
    on scratch copies of the lane's arrays: tracing does not change the run); the start row
    (`start`) takes the slips of that evaluation."""
    for s in range(N_STATE):
        y[s] = _get(st, s, l)
    _lane_arrays(st, l, law, sidx, guess)
    _rhs(y, dy, 0, law, sidx, guess, p, geo, surfs, sc, wbuf, tgt, inv)
    trace_row[T_TIME] = t
    trace_row[T_VX] = y[S_VX]
    trace_row[T_VY] = y[S_VY]
    trace_row[T_SPEED] = math.sqrt(y[S_VX] ** 2 + y[S_VY] ** 2)
    trace_row[T_YR] = y[S_YR]
    trace_row[T_PSI] = y[S_PSI]
    trace_row[T_X] = y[S_X]
    trace_row[T_Y] = y[S_Y]
    trace_row[T_DELTA] = y[S_DELTA]
    trace_row[T_AX] = guess[0, 0]
    trace_row[T_AY] = guess[1, 0]
    trace_row[T_DIST] = _get(st, R_DIST, l)
    for j in range(4):
        trace_row[T_WV + j] = y[S_W + j] * p[P_R]
        trace_row[T_SLIP + j] = _get(st, R_SLIP + j, l) if not start else sc[W_SLIP, j]
        trace_row[T_TARGET + j] = surfs[sidx[j, 0], SF_TARGET]
        trace_row[T_FZ + j] = sc[W_FZ, j]
        trace_row[T_TB + j] = p[P_KQ] * y[S_Q + j]
        trace_row[T_FX + j] = sc[W_FXW, j]
        trace_row[T_SURF + j] = sidx[j, 0]


def scratch() -> tuple[np.ndarray, ...]:
    """The scratch arrays `simulate_abs_vehicle` works in (it allocates nothing: compiled
    without reference counting), one tuple per call (a call on another thread needs its own):
    the scalar passes' state, stage derivatives, stage point, derivative column, wheel laws,
    surface indices, load guess, evaluation scratch, wheel speeds, targets and inverses, then the
    lane rows `st`, the candidate in each lane and each wheel's first gain column."""
    return (
        np.empty(N_STATE),
        np.empty((4, N_STATE)),
        np.empty(N_STATE),
        np.empty((N_STATE, 1)),
        np.empty((N_LAW, 4, 1)),
        np.empty((4, 1), dtype=np.int64),
        np.empty((2, 1)),
        np.empty((N_SCRATCH, 4)),
        np.empty(4),
        np.empty(4),
        np.empty(4),
        np.empty(N_ROWS * LANES),
        np.empty(LANES, dtype=np.int64),
        np.empty(4, dtype=np.int64),
    )
