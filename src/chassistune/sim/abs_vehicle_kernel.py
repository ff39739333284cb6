"""Compiled closed loop of the 7-DOF vehicle ABS (DESIGN 3.3) over a population of candidates.

One kernel serves every wheel controller (an integer selects the law) and both paths: a batch of
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
at v_stop (CG speed) is located by linear interpolation inside the last step.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from chassistune._branchfree import select
from chassistune.controllers.fuzzy_pid import fuzzy_pid_gains
from chassistune.controllers.pid import pid_step
from chassistune.controllers.switching import (
    no_abs_command,
    threshold_step,
    wheel_deceleration_sample,
)
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
from chassistune.sim.layout import Layout, Slot

WHEELS = ("fl", "fr", "rl", "rr")
CONTROLLER_KINDS = ("none", "pid", "threshold", "fuzzy-pid")
"""The kernel's runtime switch of the wheel law: controller name -> its index here."""
C_NONE, C_PID, C_THRESHOLD, C_FUZZY_PID = range(len(CONTROLLER_KINDS))
CONTROLLER_LAYOUT = WL.CONTROLLER
"""The controller vector: the single wheel's (sample period, amplitude, threshold settings)."""
Q_TS = CONTROLLER_LAYOUT["ts_s"]
Q_AMPLITUDE = CONTROLLER_LAYOUT["amplitude"]
Q_DECEL = CONTROLLER_LAYOUT["decel_threshold_m_s2"]
Q_ACCEL = CONTROLLER_LAYOUT["accel_threshold_m_s2"]
Q_SLIP_MARGIN = CONTROLLER_LAYOUT["slip_margin"]
Q_SLOW = CONTROLLER_LAYOUT["slow_fraction"]

PLANT_LAYOUT = Layout("abs-vehicle plant", (
    Slot("mass_kg", "kg"),
    Slot("yaw_inertia_kg_m2", "kg m^2"),
    Slot("wheel_inertia_kg_m2", "kg m^2"),
    Slot("wheel_radius_m", "m"),
    Slot("v0_m_s", "m/s"),
    Slot("actuator_gain", "-"),
    Slot("actuator_tau_s", "s"),
    Slot("brake_gain", "N m/unit"),
    Slot("q_max", "unit"),
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
    Slot("split_by_road", "-", "1: split-mu surface from the contact point's global Y; 0: by "
         "the wheel's side of the car"),
    Slot("driver", "-", "1: counter-steering driver, 0: steering fixed at 0"),
    Slot("heading_gain", "rad/rad"),
    Slot("yaw_rate_gain_s", "s"),
    Slot("max_steer_rad", "rad"),
    Slot("steer_tau_s", "s"),
    Slot("select_low", "-", "1: one rear channel on min(e_rl, e_rr)"),
    Slot("axle_gains", "-", "1: gains (front row, rear row) per axle"),
    Slot("yaw_window_s", "s", "window of the yaw metrics"),
))
GEOMETRY_LAYOUT = Layout("abs-vehicle geometry rows (columns fl, fr, rl, rr)", (
    Slot("x_m", "m", "wheel position forward of the CG"),
    Slot("y_m", "m", "wheel position left of the CG"),
    Slot("static_load_n", "N", "Fz0_i"),
    Slot("load_per_ax", "N/(m/s^2)", "A_i"),
    Slot("load_per_ay", "N/(m/s^2)", "B_i"),
))
STATE_LAYOUT = Layout("abs-vehicle state rows", (
    Slot("vx", "m/s"), Slot("vy", "m/s"), Slot("yaw_rate", "rad/s"), Slot("x", "m"),
    Slot("y", "m"), Slot("heading", "rad"), Slot("steer", "rad"),
    *(Slot(f"w_{w}", "rad/s") for w in WHEELS),
    *(Slot(f"q_{w}", "unit") for w in WHEELS),
    *(Slot(f"qrate_{w}", "unit/s") for w in WHEELS),
    *(Slot(f"z_{w}", "s") for w in WHEELS),
    *(Slot(f"xf_{w}", "-") for w in WHEELS),
))
METRIC_LAYOUT = Layout("abs-vehicle metrics", (
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
    *(Slot(f"lock_time_{w}_s", "s", "first time w R < lock_ratio |V| (NaN: never)")
      for w in WHEELS),
    Slot("load_iterations_max", "-", "most Newton iterations of one load solve"),
    Slot("n_trace", "-", "trace rows written"),
))
TRACE_LAYOUT = Layout("abs-vehicle trace", (
    Slot("time_s", "s"), Slot("vx_m_s", "m/s"), Slot("vy_m_s", "m/s"),
    Slot("speed_m_s", "m/s"), Slot("yaw_rate_rad_s", "rad/s"), Slot("heading_rad", "rad"),
    Slot("x_m", "m"), Slot("y_m", "m"), Slot("steer_rad", "rad"), Slot("ax_m_s2", "m/s^2"),
    Slot("ay_m_s2", "m/s^2"), Slot("distance_m", "m"),
    *(Slot(f"wheel_speed_{w}_m_s", "m/s") for w in WHEELS),
    *(Slot(f"slip_{w}", "-") for w in WHEELS),
    *(Slot(f"target_slip_{w}", "-") for w in WHEELS),
    *(Slot(f"load_{w}_n", "N") for w in WHEELS),
    *(Slot(f"brake_torque_{w}_n_m", "N m") for w in WHEELS),
    *(Slot(f"fx_{w}_n", "N", "wheel-frame longitudinal tire force") for w in WHEELS),
    *(Slot(f"surface_{w}", "-", "index of the surface under the wheel") for w in WHEELS),
))

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

# the wheel laws' gains and held command per wheel and lane: law[LAW_*, j, i]
LAW_KP, LAW_KI, LAW_KD, LAW_U0 = range(4)
N_LAW = 4

# lane-local copy of each wheel's surface (rows of `ls` (4, N_LANE_SURF, n)), kept in step with
# the surface index so that the vector pass reads contiguous lanes instead of gathering
L_ST, L_RISE, L_FALL0, L_FALL1, L_TARGET = range(5)
N_LANE_SURF = 5

# scratch rows of one evaluation (columns: the wheels): the physics' work rows, then ours
W_SX, W_VR, W_CS, W_SN, W_FZ, W_FXW, W_FXB, W_FYB = WK_SX, WK_VR, WK_CS, WK_SN, WK_FZ, WK_FXW, \
    WK_FXB, WK_FYB
W_SLIP, W_VABS, W_E = N_WORK, N_WORK + 1, N_WORK + 2
N_SCRATCH = N_WORK + 3


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _kinematics(vx, vy, r, delta, w, p, geo, sc):
    """Wheel-frame slips of the four wheels into the scratch rows (front wheels steered)."""
    if delta != 0.0:
        cd = math.cos(delta)
        sd = math.sin(delta)
    else:
        cd = 1.0
        sd = 0.0
    r_w = p[P_R]
    vmin = p[P_VMIN]
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
        vabs = max(math.sqrt(uw * uw + vw * vw), vmin)
        inv = 1.0 / vabs
        sx = (uw - w[j] * r_w) * inv
        sc[W_SX, j] = sx
        sc[W_VR, j] = vw * inv
        sc[W_VABS, j] = vabs
        sc[W_SLIP, j] = min(max(sx, 0.0), 1.0)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _select_low(sc, select_low):
    """Rear channels on the larger-slip wheel's error (select-low), fronts individual."""
    if select_low and sc[W_E, 3] < sc[W_E, 2]:
        sc[W_E, 2] = sc[W_E, 3]
    elif select_low:
        sc[W_E, 3] = sc[W_E, 2]


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _wheel_rates(w, q, qr, z, xf, e, fxw, dy, j, i, law, r_w, kq, inv_j, nf, gain,
                 inv_tau, q_max):
    """Rates of wheel j's spin, brake actuator and PID states into dy[:, i] (DESIGN 3.1, 4):
    J dw/dt = -R Fx - kq q (held at w = 0), T dqr/dt = K u - qr, dq/dt = qr held in [0, q_max],
    u = u0 + kp e + ki z + kd N (e - xf) with conditional integration. Branch-free."""
    dw = (-r_w * fxw - kq * q) * inv_j
    dy[S_W + j, i] = select((w <= 0.0) & (dw < 0.0), 0.0, dw)
    q_hi = q >= q_max
    q_lo = q <= 0.0
    u, dz, dxf = pid_step(e, z, xf, law[LAW_U0, j, i], law[LAW_KP, j, i], law[LAW_KI, j, i],
                          law[LAW_KD, j, i], nf, q_hi, q_lo)
    dy[S_QR + j, i] = (gain * u - qr) * inv_tau
    dy[S_Q + j, i] = select((q_hi & (qr > 0.0)) | (q_lo & (qr < 0.0)), 0.0, qr)
    dy[S_Z + j, i] = dz
    dy[S_XF + j, i] = dxf


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
        _wheel_rates(y[S_W + j], y[S_Q + j], y[S_QR + j], y[S_Z + j], y[S_XF + j], sc[W_E, j],
                     sc[W_FXW, j], dy, j, i, law, p[P_R], p[P_KQ], inv[1], p[P_NF],
                     p[P_K], inv[2], p[P_QMAX])
    return it


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _straight_wheel(vx, w, j, i, ls, r_w, vmin):
    """Slip and force per unit load of wheel j of lane i in straight-line braking (r = vy = 0,
    no steering): `_kinematics` and `straight_force_per_load` reduced to that case, bit for bit."""
    vabs = max(math.sqrt(vx * vx), vmin)
    sx = (vx - w * r_w) * (1.0 / vabs)
    s = abs(sx)
    sc = min(s, 1.0)
    mu = ls[j, L_RISE, i] * sc if sc <= ls[j, L_ST, i] else (
        ls[j, L_FALL0, i] - ls[j, L_FALL1, i] * sc)
    cf = -math.copysign(mu, sx) if s > 0.0 else 0.0
    return cf, min(max(sx, 0.0), 1.0)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _pt(x, k_in, c, row, i):
    """Stage point of state row `row` of lane i."""
    return rk4_point(x[row, i], c, k_in[row, i])


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _lane_wheel_rates(x, k_in, c, j, i, e, fxw, k_out, law, r_w, kq, inv_j, nf, gain, inv_tau,
                      q_max):
    """`_wheel_rates` of wheel j of lane i at the stage point x + c k_in."""
    _wheel_rates(_pt(x, k_in, c, S_W + j, i), _pt(x, k_in, c, S_Q + j, i),
                 _pt(x, k_in, c, S_QR + j, i), _pt(x, k_in, c, S_Z + j, i),
                 _pt(x, k_in, c, S_XF + j, i), e, fxw, k_out, j, i, law, r_w, kq, inv_j, nf, gain,
                 inv_tau, q_max)


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _stage(n, m, active, x, k_in, c, k_out, law, sidx, ls, guess, flag, p, geo, surfs,
           sc, y, wbuf, tgt, iters, inv):
    """One RK4 stage, k_out = f(x + c k_in), in two passes.

    Pass 1 runs every lane (candidate column) through the straight-line case in one branch-free
    loop the compiler vectorizes across candidates: no yaw, no lateral velocity, heading and
    steering at 0, loads in closed form. Lanes where that case does not hold are flagged; pass 2
    recomputes them (running candidates only) with the general right-hand side `_rhs`, which
    starts its load iteration from the lane's last general solution (`guess`). Both
    passes evaluate the same formulas in the same order: a lane's numbers do not depend on the
    pass, nor on its neighbours.
    """
    mass = p[P_MASS]
    driver = p[P_DRIVER] != 0.0
    select_low = p[P_SELECT_LOW] != 0.0
    fz00 = geo[G_FZ0, 0]
    fz01 = geo[G_FZ0, 1]
    fz02 = geo[G_FZ0, 2]
    fz03 = geo[G_FZ0, 3]
    a0 = geo[G_A, 0]
    a1 = geo[G_A, 1]
    a2 = geo[G_A, 2]
    a3 = geo[G_A, 3]
    x0 = geo[G_X, 0]
    x1 = geo[G_X, 1]
    x2 = geo[G_X, 2]
    x3 = geo[G_X, 3]
    y0 = geo[G_Y, 0]
    y1 = geo[G_Y, 1]
    y2 = geo[G_Y, 2]
    y3 = geo[G_Y, 3]
    r_w = p[P_R]
    vmin = p[P_VMIN]
    kq = p[P_KQ]
    nf = p[P_NF]
    gain = p[P_K]
    q_max = p[P_QMAX]
    kpsi = p[P_KPSI]
    kr = p[P_KR]
    dmax = p[P_DMAX]
    inv_iz = inv[0]
    inv_j = inv[1]
    inv_tau = inv[2]
    inv_st = inv[3]
    for i in range(n):
        vx = _pt(x, k_in, c, S_VX, i)
        vy = _pt(x, k_in, c, S_VY, i)
        r = _pt(x, k_in, c, S_YR, i)
        psi = _pt(x, k_in, c, S_PSI, i)
        delta = _pt(x, k_in, c, S_DELTA, i)
        c0, s0 = _straight_wheel(vx, _pt(x, k_in, c, S_W, i), 0, i, ls, r_w, vmin)
        c1, s1 = _straight_wheel(vx, _pt(x, k_in, c, S_W + 1, i), 1, i, ls, r_w, vmin)
        c2, s2 = _straight_wheel(vx, _pt(x, k_in, c, S_W + 2, i), 2, i, ls, r_w, vmin)
        c3, s3 = _straight_wheel(vx, _pt(x, k_in, c, S_W + 3, i), 3, i, ls, r_w, vmin)
        num = 0.0
        num += c0 * fz00
        num += c1 * fz01
        num += c2 * fz02
        num += c3 * fz03
        den = mass
        den -= c0 * a0
        den -= c1 * a1
        den -= c2 * a2
        den -= c3 * a3
        ax = num / den
        fz0 = fz00 + a0 * ax
        fz1 = fz01 + a1 * ax
        fz2 = fz02 + a2 * ax
        fz3 = fz03 + a3 * ax
        ok = ((vy == 0.0) & (r == 0.0) & (psi == 0.0) & (delta == 0.0) & (fz0 >= 0.0)
              & (fz1 >= 0.0) & (fz2 >= 0.0) & (fz3 >= 0.0))
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
        mz += x0 * 0.0 - y0 * fx0
        mz += x1 * 0.0 - y1 * fx1
        mz += x2 * 0.0 - y2 * fx2
        mz += x3 * 0.0 - y3 * fx3
        k_out[S_VX, i] = ax + vy * r
        k_out[S_VY, i] = 0.0 - vx * r
        k_out[S_YR, i] = mz * inv_iz
        k_out[S_X, i] = vx
        k_out[S_Y, i] = vy
        k_out[S_PSI, i] = r
        cmd = min(max(-kpsi * psi - kr * r, -dmax), dmax)
        k_out[S_DELTA, i] = (cmd - delta) * inv_st if driver else 0.0
        e0 = ls[0, L_TARGET, i] - s0
        e1 = ls[1, L_TARGET, i] - s1
        e2 = ls[2, L_TARGET, i] - s2
        e3 = ls[3, L_TARGET, i] - s3
        low = e3 < e2
        e2s = e3 if (select_low & low) else e2
        e3s = e2 if (select_low & ~low) else e3
        _lane_wheel_rates(x, k_in, c, 0, i, e0, fx0, k_out, law, r_w, kq, inv_j, nf,
                          gain, inv_tau, q_max)
        _lane_wheel_rates(x, k_in, c, 1, i, e1, fx1, k_out, law, r_w, kq, inv_j, nf,
                          gain, inv_tau, q_max)
        _lane_wheel_rates(x, k_in, c, 2, i, e2s, fx2, k_out, law, r_w, kq, inv_j, nf,
                          gain, inv_tau, q_max)
        _lane_wheel_rates(x, k_in, c, 3, i, e3s, fx3, k_out, law, r_w, kq, inv_j, nf,
                          gain, inv_tau, q_max)
        k_out[K_FLAG, i] = 0.0 if ok else 1.0
    for jj in range(m):
        i = active[jj]
        if k_out[K_FLAG, i] != 0.0:
            for s in range(N_STATE):
                y[s] = rk4_point(x[s, i], c, k_in[s, i])
            it = _rhs(y, k_out, i, law, sidx, guess, p, geo, surfs, sc, wbuf, tgt, inv)
            iters[i] = max(iters[i], it)


@numba.njit(cache=True, nogil=True, error_model="numpy", inline="always")
def _update_surfaces(x, i, p, geo, sidx, surfs, ls):
    """Surface under each wheel from its contact point's global position (mu-jump, split-mu),
    and its lane-local copy."""
    kind = p[P_ROAD]
    if kind in (ROAD_MU_JUMP, ROAD_SPLIT):
        psi = x[S_PSI, i]
        cp = math.cos(psi) if psi != 0.0 else 1.0
        sp = math.sin(psi) if psi != 0.0 else 0.0
        for j in range(4):
            if kind == ROAD_MU_JUMP:
                gx = x[S_X, i] + geo[G_X, j] * cp - geo[G_Y, j] * sp
                sidx[j, i] = 1 if gx >= p[P_XJUMP] else 0
            elif p[P_SPLIT_ROAD] != 0.0:
                gy = x[S_Y, i] + geo[G_X, j] * sp + geo[G_Y, j] * cp
                sidx[j, i] = 0 if gy >= p[P_YSPLIT] else 1
            else:
                sidx[j, i] = 0 if geo[G_Y, j] > 0.0 else 1
    for j in range(4):
        k = sidx[j, i]
        ls[j, L_ST, i] = surfs[k, SF_ST]
        ls[j, L_RISE, i] = surfs[k, SF_RISE]
        ls[j, L_FALL0, i] = surfs[k, SF_FALL0]
        ls[j, L_FALL1, i] = surfs[k, SF_FALL1]
        ls[j, L_TARGET, i] = surfs[k, SF_TARGET]


@numba.njit(cache=True, nogil=True, error_model="numpy")
def simulate_abs_vehicle(gains, p, geo, surfs, ctrl_kind, c, table, trace, out):
    """Simulate every row of `gains` (n, G): the wheel law's gains in catalogue order, twice
    (front, then rear) when p[axle_gains] is 1.

    p: PLANT_LAYOUT vector; geo: GEOMETRY_LAYOUT rows x 4 wheels; surfs: surface rows (SF_*
    columns of `plants.abs_vehicle`), index 0 and 1; c: the single wheel's controller vector
    (ts_s, amplitude, thresholds); table: a compiled fuzzy surface (any surface for other laws).
    Writes each candidate's METRIC_LAYOUT row into out (n, N_METRICS); when `trace` has rows
    (n must be 1), also the TRACE_LAYOUT time series, one row per step.
    """
    n = gains.shape[0]
    dt = p[P_DT]
    hs = 0.5 * dt
    h6 = dt / 6.0
    r_w = p[P_R]
    v_stop = p[P_VSTOP]
    q_max = p[P_QMAX]
    window = p[P_WINDOW]
    n_steps = math.ceil(p[P_TMAX] / dt - 1e-9)
    select_low = p[P_SELECT_LOW] != 0.0
    moving_surfaces = p[P_ROAD] in (ROAD_MU_JUMP, ROAD_SPLIT)  # else sidx, ls fixed from t = 0
    n_g = gains.shape[1] // 2 if p[P_AXLE] != 0.0 else gains.shape[1]
    law = np.zeros((N_LAW, 4, n))
    col0 = np.zeros(4, dtype=np.int64)  # first gain column of each wheel
    for j in range(2, 4):
        col0[j] = n_g if p[P_AXLE] != 0.0 else 0
    if ctrl_kind == C_PID:
        for i in range(n):
            for j in range(4):
                law[LAW_KP, j, i] = gains[i, col0[j]]
                law[LAW_KI, j, i] = gains[i, col0[j] + 1]
                law[LAW_KD, j, i] = gains[i, col0[j] + 2]
    x = np.zeros((N_STATE, n))
    x[S_VX, :] = p[P_V0]
    for j in range(4):
        x[S_W + j, :] = p[P_V0] / r_w
    sidx = np.zeros((4, n), dtype=np.int64)
    ls = np.zeros((4, N_LANE_SURF, n))
    flag = np.zeros(n, dtype=np.int64)
    sc = np.zeros((N_SCRATCH, 4))
    for i in range(n):
        _update_surfaces(x, i, p, geo, sidx, surfs, ls)
        for j in range(4):
            sc[W_E, j] = surfs[sidx[j, i], SF_TARGET]  # e(0): the wheels roll freely
        _select_low(sc, select_low)
        for j in range(4):
            x[S_XF + j, i] = sc[W_E, j]  # the derivative filter starts at e(0): no kick
    k1 = np.zeros((N_STATE + 1, n))  # row K_FLAG: lanes the straight pass could not handle
    k2 = np.zeros((N_STATE + 1, n))
    k3 = np.zeros((N_STATE + 1, n))
    k4 = np.zeros((N_STATE + 1, n))
    guess = np.zeros((2, n))
    y = np.zeros(N_STATE)
    dy = np.zeros((N_STATE, 1))
    inv = np.array([1.0 / p[P_IZ], 1.0 / p[P_J], 1.0 / p[P_TAU], 1.0 / p[P_STAU]])
    wbuf = np.zeros(4)
    tgt = np.zeros(4)
    iters = np.zeros(n)
    slip = np.zeros((4, n))  # clipped slips at the last step end
    err = np.zeros((4, n))  # slip errors at the last step end (after the surface update)
    for i in range(n):
        for j in range(4):
            err[j, i] = surfs[sidx[j, i], SF_TARGET]
    w_sampled = np.zeros((4, n))
    for j in range(4):
        w_sampled[j, :] = p[P_V0] / r_w
    aw = np.zeros((4, n))
    phase = np.zeros((4, n), dtype=np.int64)
    speed = np.full(n, p[P_V0])
    dist = np.zeros(n)
    iae = np.zeros(n)
    itae = np.zeros(n)
    ise = np.zeros(n)
    sint = np.zeros((4, n))
    locked = np.zeros(n)
    lock_t = np.full((4, n), np.nan)
    all_t = np.full(n, np.nan)
    all_v = np.full(n, np.nan)
    all_d = np.full(n, np.nan)
    yaw_pk1 = np.zeros(n)
    psi1 = np.full(n, np.nan)
    y1 = np.full(n, np.nan)
    yaw_pk = np.zeros(n)
    spin_t = np.full(n, np.nan)
    status = np.full(n, float(STATUS_TIMEOUT))
    t_end = np.full(n, n_steps * dt)
    steps_per_sample = max(1, round(c[Q_TS] / dt))
    active = np.arange(n)
    running = np.ones(n, dtype=np.bool_)
    m = n
    n_trace = trace.shape[0]
    rows = 0
    if n_trace > 0:
        _trace_row(trace, 0, 0.0, x, 0, dist, slip, sidx, law, guess, p, geo, surfs,
                   sc, y, dy, wbuf, tgt, inv)
        rows = 1
    for k in range(n_steps):
        if m == 0:
            break
        t = k * dt
        if ctrl_kind != C_PID and k % steps_per_sample == 0:  # sampled laws: own period ts
            ts = steps_per_sample * dt
            for jj in range(m):
                i = active[jj]
                for j in range(4):
                    sc[W_E, j] = err[j, i]
                _select_low(sc, select_low)
                for j in range(4):
                    e = sc[W_E, j]
                    # select-low: a rear channel reads the wheel whose error it took
                    src = j
                    if select_low and j >= 2:
                        src = 3 if err[3, i] < err[2, i] else 2
                    if ctrl_kind == C_FUZZY_PID:
                        ec = p[P_NF] * (e - x[S_XF + j, i])
                        g0 = col0[j]
                        kp_s, ki_s, kd_s = fuzzy_pid_gains(
                            table, e, ec, gains[i, g0], gains[i, g0 + 1], gains[i, g0 + 2],
                            gains[i, g0 + 3], gains[i, g0 + 4], gains[i, g0 + 5],
                            gains[i, g0 + 6], gains[i, g0 + 7])
                        law[LAW_KP, j, i] = kp_s
                        law[LAW_KI, j, i] = ki_s
                        law[LAW_KD, j, i] = kd_s
                    elif ctrl_kind == C_THRESHOLD:
                        if k > 0:
                            aw[j, i] = wheel_deceleration_sample(x[S_W + src, i],
                                                                 w_sampled[src, i], r_w, ts)
                        u0_s, ph = threshold_step(
                            phase[j, i], slip[src, i], surfs[sidx[src, i], SF_TARGET], aw[j, i],
                            c[Q_AMPLITUDE], c[Q_DECEL], c[Q_ACCEL], c[Q_SLIP_MARGIN], c[Q_SLOW])
                        law[LAW_U0, j, i] = u0_s
                        phase[j, i] = ph
                    else:
                        law[LAW_U0, j, i] = no_abs_command(c[Q_AMPLITUDE])
                for j in range(4):
                    w_sampled[j, i] = x[S_W + j, i]
        _stage(n, m, active, x, k4, 0.0, k1, law, sidx, ls, guess, flag,
               p, geo, surfs, sc, y, wbuf, tgt, iters, inv)
        _stage(n, m, active, x, k1, hs, k2, law, sidx, ls, guess, flag,
               p, geo, surfs, sc, y, wbuf, tgt, iters, inv)
        _stage(n, m, active, x, k2, hs, k3, law, sidx, ls, guess, flag,
               p, geo, surfs, sc, y, wbuf, tgt, iters, inv)
        _stage(n, m, active, x, k3, dt, k4, law, sidx, ls, guess, flag,
               p, geo, surfs, sc, y, wbuf, tgt, iters, inv)
        for s in range(N_STATE):  # branch-free over every lane; ended lanes keep their state
            for i in range(n):
                x[s, i] = select(running[i], rk4_update(x[s, i], h6, k1[s, i], k2[s, i],
                                                        k3[s, i], k4[s, i]), x[s, i])
        for j in range(4):
            for i in range(n):
                x[S_W + j, i] = max(x[S_W + j, i], 0.0)
                x[S_Q + j, i] = min(max(x[S_Q + j, i], 0.0), q_max)
        jj = 0
        while jj < m:
            i = active[jj]
            vx = x[S_VX, i]
            vy = x[S_VY, i]
            sp_new = math.sqrt(vx * vx + vy * vy)
            sp_old = speed[i]
            stop = sp_new <= v_stop
            frac = crossing_fraction(sp_old, sp_new, v_stop, stop)
            h = frac * dt
            sp_end = v_stop if stop else sp_new
            dist[i] += trapezoid(sp_old, sp_end, h)
            for j in range(4):
                wbuf[j] = x[S_W + j, i]
            _kinematics(vx, vy, x[S_YR, i], x[S_DELTA, i], wbuf, p, geo, sc)
            all_still = True
            for j in range(4):
                s_new = sc[W_SLIP, j]
                s_end = slip[j, i] + frac * (s_new - slip[j, i])
                target = surfs[sidx[j, i], SF_TARGET]
                d_iae, d_itae, d_ise = error_integrals(err[j, i], target - s_end, t, h)
                iae[i] += d_iae
                itae[i] += d_itae
                ise[i] += d_ise
                sint[j, i] += trapezoid(slip[j, i], s_end, h)
                slip[j, i] = s_new
                if sp_new > v_stop and x[S_W + j, i] * r_w < p[P_LOCK] * sc[W_VABS, j]:
                    locked[i] += dt
                    if lock_t[j, i] != lock_t[j, i]:
                        lock_t[j, i] = t + dt
                all_still = all_still and x[S_W + j, i] == 0.0
            if all_still and all_t[i] != all_t[i] and sp_new > v_stop:
                all_t[i] = t + dt
                all_v[i] = sp_new
                all_d[i] = dist[i]
            if moving_surfaces:
                _update_surfaces(x, i, p, geo, sidx, surfs, ls)
            for j in range(4):
                err[j, i] = surfs[sidx[j, i], SF_TARGET] - slip[j, i]
            r_now = x[S_YR, i]
            psi_now = x[S_PSI, i]
            if t + 0.5 * dt < window:
                if abs(r_now) > abs(yaw_pk1[i]):
                    yaw_pk1[i] = r_now
                if t + 1.5 * dt >= window:
                    psi1[i] = psi_now
                    y1[i] = x[S_Y, i]
            if spin_t[i] != spin_t[i]:
                if abs(r_now) > abs(yaw_pk[i]):
                    yaw_pk[i] = r_now
                if abs(psi_now) >= 0.5 * math.pi:
                    spin_t[i] = t + dt
            speed[i] = sp_new
            check = sp_new + r_now + psi_now + itae[i] + x[S_Q, i] + x[S_Z, i] + x[S_W, i]
            ended = True
            if check - check != 0.0:
                status[i] = STATUS_DIVERGED
                t_end[i] = t
            elif stop:
                status[i] = STATUS_STOPPED
                t_end[i] = t + h
            elif dist[i] > p[P_HOPELESS]:
                status[i] = STATUS_HOPELESS
                t_end[i] = t + dt
            else:
                ended = False
            if ended:
                running[i] = False
                m -= 1
                active[jj] = active[m]
                active[m] = i
            else:
                jj += 1
        if n_trace > 0 and rows < n_trace:
            _trace_row(trace, rows, min(t + dt, t_end[0]), x, 0, dist, slip, sidx, law,
                       guess, p, geo, surfs, sc, y, dy, wbuf, tgt, inv)
            if status[0] == STATUS_STOPPED:
                trace[rows, T_SPEED] = max(trace[rows, T_SPEED], v_stop)
            rows += 1
    for i in range(n):
        out[i, :] = 0.0
        out[i, M_STATUS] = status[i]
        out[i, M_TIME] = t_end[i]
        out[i, M_DIST] = dist[i]
        out[i, M_XSTOP] = x[S_X, i]
        out[i, M_IAE] = iae[i]
        out[i, M_ITAE] = itae[i]
        out[i, M_ISE] = ise[i]
        out[i, M_LOCKED] = locked[i]
        out[i, M_YAWPK1] = yaw_pk1[i]
        out[i, M_PSI1] = math.degrees(psi1[i] if psi1[i] == psi1[i] else x[S_PSI, i])
        out[i, M_Y1] = y1[i] if y1[i] == y1[i] else x[S_Y, i]
        out[i, M_YAWPK] = yaw_pk[i]
        out[i, M_SPUN] = 0.0 if spin_t[i] != spin_t[i] else 1.0
        out[i, M_SPIN_T] = spin_t[i]
        out[i, M_PSI_END] = math.degrees(x[S_PSI, i])
        out[i, M_Y_END] = x[S_Y, i]
        out[i, M_ALL_T] = all_t[i]
        out[i, M_ALL_V] = all_v[i]
        out[i, M_ALL_D] = all_d[i]
        for j in range(4):
            out[i, M_MEAN_SLIP + j] = sint[j, i] / t_end[i] if t_end[i] > 0.0 else 0.0
            out[i, M_LOCK_T + j] = lock_t[j, i]
        out[i, M_ITER] = iters[i]
        out[i, M_NTRACE] = rows


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _trace_row(trace, row, t, x, i, dist, slip, sidx, law, guess, p, geo, surfs, sc,
               y, dy, wbuf, tgt, inv):
    """One trace row of candidate i (a batch of one: i = 0): its state, and loads and forces
    re-evaluated at it (dy: a throw-away (N_STATE, 1) array)."""
    for s in range(N_STATE):
        y[s] = x[s, i]
    g0 = guess[0, i]
    g1 = guess[1, i]
    _rhs(y, dy, i, law, sidx, guess, p, geo, surfs, sc, wbuf, tgt, inv)
    ax = guess[0, i]
    ay = guess[1, i]
    guess[0, i] = g0  # tracing must not change the run
    guess[1, i] = g1
    trace[row, T_TIME] = t
    trace[row, T_VX] = x[S_VX, i]
    trace[row, T_VY] = x[S_VY, i]
    trace[row, T_SPEED] = math.sqrt(x[S_VX, i] ** 2 + x[S_VY, i] ** 2)
    trace[row, T_YR] = x[S_YR, i]
    trace[row, T_PSI] = x[S_PSI, i]
    trace[row, T_X] = x[S_X, i]
    trace[row, T_Y] = x[S_Y, i]
    trace[row, T_DELTA] = x[S_DELTA, i]
    trace[row, T_AX] = ax
    trace[row, T_AY] = ay
    trace[row, T_DIST] = dist[i]
    for j in range(4):
        trace[row, T_WV + j] = x[S_W + j, i] * p[P_R]
        trace[row, T_SLIP + j] = slip[j, i] if row > 0 else sc[W_SLIP, j]
        trace[row, T_TARGET + j] = surfs[sidx[j, i], SF_TARGET]
        trace[row, T_FZ + j] = sc[W_FZ, j]
        trace[row, T_TB + j] = p[P_KQ] * x[S_Q + j, i]
        trace[row, T_FX + j] = sc[W_FXW, j]
        trace[row, T_SURF + j] = sidx[j, i]
