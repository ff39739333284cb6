"""Declared inputs, outputs and working rows of the 7-DOF vehicle ABS kernel
(`sim.abs_vehicle_kernel`).

Every slot of the plant vector, the geometry rows, the state, the metrics row, the trace row, the
kernel's constants (one tuple, `abs_vehicle_lane.constants`) and a lane's rows is declared here
once, by name; the kernel's modules take their integer slot constants from these layouts (numba
freezes module-level integers as compile-time constants) and the scenario packs and decodes
through them. A new metric or trace signal: one `Slot` line here plus the kernel line that
writes it.
"""

from __future__ import annotations

from chassistune.controllers.laws import registry
from chassistune.layout import Layout, Slot
from chassistune.plants.abs_vehicle import (
    GEO_A,
    GEO_B,
    GEO_FZ0,
    GEO_X,
    GEO_Y,
    N_WORK,
    WK_CS,
    WK_FXB,
    WK_FXW,
    WK_FYB,
    WK_FZ,
    WK_SN,
    WK_SX,
    WK_VR,
)
from chassistune.sim import abs_wheel_layout as WL

MEMORY = registry.slots("memory")
"""Memory slots of each wheel's law (`Law.state`): the most any registered law keeps."""

WHEELS = ("fl", "fr", "rl", "rr")
CONTROLLER_LAYOUT = WL.CONTROLLER
"""The controller vector: the single wheel's (sample period, amplitude, threshold settings)."""
Q_TS = CONTROLLER_LAYOUT["ts_s"]

STATUS_NAMES = WL.STATUS_NAMES
"""How a run ended: the code in the metrics' `status` column indexes this tuple."""
STATUS_STOPPED = STATUS_NAMES.index("stopped")
STATUS_HOPELESS = STATUS_NAMES.index("hopeless")
STATUS_TIMEOUT = STATUS_NAMES.index("timeout")
STATUS_DIVERGED = STATUS_NAMES.index("diverged")

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
        Slot("brake_gain", "N m/preset unit", "kq: the mean of the four wheels' brake gains"),
        Slot(
            "front_brake_share",
            "-",
            "the front axle's share s of the brake torque at equal pressure: 2 s kq on a front "
            "wheel, 2 (1 - s) kq on a rear one (the measured cars: CommonRoad's T_sb)",
        ),
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
        Slot(
            "target_gain_column",
            "-",
            "the gain column of a fixed target slip (road knowledge fixed); -1: the target of "
            "the surface under each wheel",
        ),
        Slot(
            "gma_gain_column",
            "-",
            "the gain column of the yaw-moment build-up rate r_gma (controllers.yaw_moment_delay); "
            "-1: no delay",
        ),
        *(
            Slot(
                f"relaxation_length_{w}_m",
                "m",
                "the wheel's longitudinal relaxation length sigma_kappa (0: the kinematic slip)",
            )
            for w in WHEELS
        ),
        *(
            Slot(
                f"lateral_relaxation_length_{w}_m",
                "m",
                "the wheel's lateral relaxation length sigma_alpha (0: the kinematic slip angle)",
            )
            for w in WHEELS
        ),
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
        *(
            Slot(
                f"lagged_slip_{w}",
                "-",
                "the tire's lagged longitudinal slip s' = -kappa' (`abs_vehicle_lag`; 0 while the "
                "wheel's relaxation length is 0)",
            )
            for w in WHEELS
        ),
        *(Slot(f"lagged_tan_alpha_{w}", "-", "the tire's lagged tan(alpha')") for w in WHEELS),
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
        Slot("status", "-", "index into STATUS_NAMES"),
        Slot("stop_time_s", "s"),
        Slot("stop_distance_m", "m", "CG path length"),
        Slot("stop_x_m", "m", "global X of the CG at the stop"),
        Slot("slip_iae", "s", "sum over the wheels"),
        Slot("slip_itae", "s^2", "sum over the wheels"),
        Slot("slip_ise", "s", "sum over the wheels"),
        Slot(
            "locked_time_s",
            "s",
            "each wheel's time locked while moving, summed over the four wheels (all four "
            "locked for 1 s count 4 s)",
        ),
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
        *(
            Slot(
                f"slip_{w}",
                "-",
                "the slip the ECU sees, (u - w R)/|V| clipped to [0, 1]; shown as 1 where the "
                "wheel stands still while the car moves (`locked_slip_shown`)",
            )
            for w in WHEELS
        ),
        *(Slot(f"target_slip_{w}", "-") for w in WHEELS),
        *(Slot(f"load_{w}_n", "N") for w in WHEELS),
        *(Slot(f"brake_torque_{w}_n_m", "N m") for w in WHEELS),
        *(Slot(f"fx_{w}_n", "N", "wheel-frame longitudinal tire force") for w in WHEELS),
        *(Slot(f"surface_{w}", "-", "index of the surface under the wheel") for w in WHEELS),
    ),
)
LAG_TRACE_LAYOUT = Layout(
    "abs-vehicle trace columns of a run with relaxation lengths (after TRACE_LAYOUT's)",
    (
        *(
            Slot(
                f"lagged_slip_{w}",
                "-",
                "the longitudinal slip the tire reads, s' = -kappa' (braking positive, over |u|; "
                "the kinematic (u - w R)/|u| where the length is 0)",
            )
            for w in WHEELS
        ),
        *(
            Slot(
                f"lagged_tan_alpha_{w}",
                "-",
                "tan(alpha') the tire reads (the kinematic v/|u| where the length is 0)",
            )
            for w in WHEELS
        ),
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
P_FRONT_SHARE = PLANT_LAYOUT["front_brake_share"]
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
P_TCOL = PLANT_LAYOUT["target_gain_column"]
P_GCOL = PLANT_LAYOUT["gma_gain_column"]
P_SIGMA_X = PLANT_LAYOUT["relaxation_length_fl_m"]
P_SIGMA_Y = PLANT_LAYOUT["lateral_relaxation_length_fl_m"]

G_X = GEOMETRY_LAYOUT["x_m"]
G_Y = GEOMETRY_LAYOUT["y_m"]
G_FZ0 = GEOMETRY_LAYOUT["static_load_n"]
G_A = GEOMETRY_LAYOUT["load_per_ax"]
G_B = GEOMETRY_LAYOUT["load_per_ay"]
if (G_X, G_Y, G_FZ0, G_A, G_B) != (GEO_X, GEO_Y, GEO_FZ0, GEO_A, GEO_B):  # pragma: no cover
    raise RuntimeError("GEOMETRY_LAYOUT must declare the rows of plants.abs_vehicle.geometry")

S_VX = STATE_LAYOUT["vx"]
S_VY = STATE_LAYOUT["vy"]
S_YR = STATE_LAYOUT["yaw_rate"]
S_X = STATE_LAYOUT["x"]
S_Y = STATE_LAYOUT["y"]
S_PSI = STATE_LAYOUT["heading"]
S_DELTA = STATE_LAYOUT["steer"]
S_LAG_X = STATE_LAYOUT["lagged_slip_fl"]
S_LAG_Y = STATE_LAYOUT["lagged_tan_alpha_fl"]
S_W = STATE_LAYOUT["w_fl"]
S_Q = STATE_LAYOUT["q_fl"]
S_QR = STATE_LAYOUT["qrate_fl"]
S_Z = STATE_LAYOUT["z_fl"]
S_XF = STATE_LAYOUT["xf_fl"]
N_STATE = len(STATE_LAYOUT)

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
T_LAG_X = N_TRACE + LAG_TRACE_LAYOUT["lagged_slip_fl"]
T_LAG_Y = N_TRACE + LAG_TRACE_LAYOUT["lagged_tan_alpha_fl"]
N_TRACE_LAGGED = N_TRACE + len(LAG_TRACE_LAYOUT)

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
W_SLIP, W_VABS = N_WORK, N_WORK + 1
N_SCRATCH = N_WORK + 2


LANES = 16
"""Candidates in flight per kernel call (a multiple of VECTOR)."""
VECTOR = 8
"""Lanes per vector iteration (8 doubles: one zmm register; two ymm)."""


def _per_wheel(name: str, unit: str, description: str = "") -> tuple[Slot, ...]:
    """One slot per wheel, fl, fr, rl, rr: a block of four consecutive slots."""
    return tuple(Slot(f"{name}_{w}", unit, description) for w in WHEELS)


GENERAL_ROWS = (
    Slot("general", "-", "1: the general pass steps the lane (`abs_vehicle_general`)"),
    *(
        Slot(f"k_prev_{s.name}", f"{s.unit}/s", "the general pass: the last stage's derivative")
        for s in STATE_LAYOUT.slots
    ),
    *(
        Slot(f"k_sum_{s.name}", f"{s.unit}/s", "the general pass: k1 + 2 k2 + 2 k3 + k4 so far")
        for s in STATE_LAYOUT.slots
    ),
    Slot("steer_rad", "rad", "the steering angle the next two rows are of"),
    Slot("steer_cos", "-", "cos of the stage's steering angle (1 at 0)"),
    Slot("steer_sin", "-", "sin of the stage's steering angle (0 at 0)"),
    Slot("heading_rad", "rad", "the heading the next two rows are of"),
    Slot("heading_cos", "-", "cos of the stage's heading (1 at 0)"),
    Slot("heading_sin", "-", "sin of the stage's heading (0 at 0)"),
    *_per_wheel("sx", "-", "the stage's longitudinal slip (u - w R)/|V| the tire reads, unclipped"),
    *_per_wheel("vr", "-", "the stage's v/|V| in the wheel frame the tire reads"),
    *_per_wheel(
        "kinematic_slip",
        "-",
        "the stage's kinematic slip clipped to [0, 1], the laws' input, where the tire reads "
        "lagged slips (`abs_vehicle_lag`)",
    ),
    *_per_wheel("wheel_cos", "-", "the wheel-to-body rotation (cos, sin)"),
    *_per_wheel("wheel_sin", "-"),
    Slot("newton_ax_m_s2", "m/s^2", "the load solve's iterate"),
    Slot("newton_ay_m_s2", "m/s^2"),
    Slot("newton_done", "-", "1: the lane's load solve has returned"),
    Slot("newton_r_ax_m_s2", "m/s^2", "the residual at the iterate (sum Fx / m - ax)"),
    Slot("newton_r_ay_m_s2", "m/s^2"),
    *_per_wheel("slip_lateral", "-", "the tire at the iterate (`combined_slip`): sy"),
    *_per_wheel("slip_norm", "-", "|s|"),
    *_per_wheel("friction", "-", "mu(min(|s|, 1))"),
    *_per_wheel("slip_cos", "-", "sx / |s|"),
    *_per_wheel("no_force", "-", "1: no force (Fz <= 0 or s = 0)"),
    *_per_wheel("mf_dfx_dfz", "-", "the Magic Formula tire at the iterate: dFx/dFz"),
    *_per_wheel("mf_dfy_dfz", "-", "dFy/dFz"),
    Slot("load_ax_m_s2", "m/s^2", "the load solve's result"),
    Slot("load_ay_m_s2", "m/s^2"),
    Slot("load_iteration", "-", "its Newton iterations"),
    *_per_wheel("fx_wheel_n", "N", "the solution's wheel-frame longitudinal force"),
    *_per_wheel("fx_body_n", "N", "the solution's body-frame forces"),
    *_per_wheel("fy_body_n", "N"),
    Slot("straight_stage", "-", "1: the stage is in the straight-line case (no guess update)"),
)
"""The general pass's working rows of a lane (`abs_vehicle_general.general_steps`): one RK4 step
of the lanes the vector pass did not commit, stage by stage over all lanes at once."""

LANE_LAYOUT = Layout(
    "abs-vehicle lane rows (row r of lane l at r * LANES + l)",
    (
        *STATE_LAYOUT.slots,
        *(
            Slot(f"k4_{s.name}", f"{s.unit}/s", "the last step's k4 (stage 1 reads it)")
            for s in STATE_LAYOUT.slots
        ),
        *_per_wheel("kp", "-", "the wheel law's held gains and command (`Law.forms`)"),
        *_per_wheel("ki", "-"),
        *_per_wheel("kd", "-"),
        *_per_wheel("u0", "-"),
        *_per_wheel("surface", "-", "surface under the wheel (1.0: the road's second)"),
        *_per_wheel("slip", "-", "clipped slip at the last step end"),
        *_per_wheel("slip_integral", "s", "integral of the slip (its time mean at the end)"),
        *_per_wheel("lock_step_s", "s", "start of the step in which the wheel first locked"),
        *_per_wheel("lock_margin_start", "m/s", "w R - lock_ratio |V| at that step's start"),
        *_per_wheel("lock_margin_end", "m/s", "w R - lock_ratio |V| at that step's end"),
        *(
            slot
            for m in range(MEMORY)
            for slot in _per_wheel(f"memory{m}", "-", "the wheel law's memory (`Law.state`)")
        ),
        *_per_wheel("w_sampled", "rad/s", "wheel speed at the last sample instant"),
        *_per_wheel("q_sampled", "unit", "brake pressure at the last sample instant"),
        Slot("distance_m", "m", "CG path length"),
        Slot("speed_m_s", "m/s", "CG speed at the last step end"),
        Slot("iae", "s"),
        Slot("itae", "s^2"),
        Slot("ise", "s"),
        Slot("locked_s", "s"),
        Slot("all_locked_time_s", "s"),
        Slot("all_locked_speed_m_s", "m/s"),
        Slot("all_locked_distance_m", "m"),
        Slot("yaw_rate_peak_1s", "rad/s"),
        Slot("heading_1s", "rad"),
        Slot("lateral_offset_1s_m", "m"),
        Slot("yaw_rate_peak", "rad/s"),
        Slot("spin_time_s", "s"),
        Slot("status", "-", "index into STATUS_NAMES"),
        Slot("t_end_s", "s", "when the run ended"),
        Slot("step", "-", "steps done"),
        Slot("ended", "-", "1: the run ended in the last step"),
        Slot("done", "-", "1: the vector pass committed the lane's step"),
        Slot("ax_m_s2", "m/s^2", "the last general load solve (the next one's start)"),
        Slot("ay_m_s2", "m/s^2"),
        Slot("load_iterations", "-", "most Newton iterations of one load solve"),
        Slot("target_slip_surface0", "-", "the law's target on surface 0 (`fill_lane`)"),
        Slot("target_slip_surface1", "-", "the law's target on surface 1"),
        Slot("gma_rate", "preset unit/s", "r_gma q_max, the front pressure gap's growth; -1: off"),
        *GENERAL_ROWS,
    ),
)
R_K4 = LANE_LAYOUT["k4_vx"]
R_KP = LANE_LAYOUT["kp_fl"]
R_KI = LANE_LAYOUT["ki_fl"]
R_KD = LANE_LAYOUT["kd_fl"]
R_U0 = LANE_LAYOUT["u0_fl"]
R_SURF = LANE_LAYOUT["surface_fl"]
R_SLIP = LANE_LAYOUT["slip_fl"]
R_SINT = LANE_LAYOUT["slip_integral_fl"]
R_LOCK_T = LANE_LAYOUT["lock_step_s_fl"]
R_LOCK_M0 = LANE_LAYOUT["lock_margin_start_fl"]
R_LOCK_M1 = LANE_LAYOUT["lock_margin_end_fl"]
R_MEM = LANE_LAYOUT["memory0_fl"]
"""Memory slot m of wheel j at row R_MEM + 4 m + j."""
R_WS = LANE_LAYOUT["w_sampled_fl"]
R_QS = LANE_LAYOUT["q_sampled_fl"]
R_DIST = LANE_LAYOUT["distance_m"]
R_SPEED = LANE_LAYOUT["speed_m_s"]
R_IAE = LANE_LAYOUT["iae"]
R_ITAE = LANE_LAYOUT["itae"]
R_ISE = LANE_LAYOUT["ise"]
R_LOCKED = LANE_LAYOUT["locked_s"]
R_ALL_T = LANE_LAYOUT["all_locked_time_s"]
R_ALL_V = LANE_LAYOUT["all_locked_speed_m_s"]
R_ALL_D = LANE_LAYOUT["all_locked_distance_m"]
R_YAWPK1 = LANE_LAYOUT["yaw_rate_peak_1s"]
R_PSI1 = LANE_LAYOUT["heading_1s"]
R_Y1 = LANE_LAYOUT["lateral_offset_1s_m"]
R_YAWPK = LANE_LAYOUT["yaw_rate_peak"]
R_SPIN_T = LANE_LAYOUT["spin_time_s"]
R_STATUS = LANE_LAYOUT["status"]
R_TEND = LANE_LAYOUT["t_end_s"]
R_STEP = LANE_LAYOUT["step"]
R_ENDED = LANE_LAYOUT["ended"]
R_DONE = LANE_LAYOUT["done"]
R_AX = LANE_LAYOUT["ax_m_s2"]
R_AY = LANE_LAYOUT["ay_m_s2"]
R_ITER = LANE_LAYOUT["load_iterations"]
R_TGT = LANE_LAYOUT["target_slip_surface0"]
R_GMA = LANE_LAYOUT["gma_rate"]
"""The law's target slip on surface s at row R_TGT + s: the surface's own, or the fixed gain."""
R_GENERAL = LANE_LAYOUT["general"]
R_KPREV = LANE_LAYOUT["k_prev_vx"]
R_KSUM = LANE_LAYOUT["k_sum_vx"]
R_STEER = LANE_LAYOUT["steer_rad"]
R_STEER_COS = LANE_LAYOUT["steer_cos"]
R_STEER_SIN = LANE_LAYOUT["steer_sin"]
R_HEAD = LANE_LAYOUT["heading_rad"]
R_HEAD_COS = LANE_LAYOUT["heading_cos"]
R_HEAD_SIN = LANE_LAYOUT["heading_sin"]
if (R_STEER_COS, R_STEER_SIN, R_HEAD_COS, R_HEAD_SIN) != (
    R_STEER + 1,
    R_STEER + 2,
    R_HEAD + 1,
    R_HEAD + 2,
):  # pragma: no cover
    raise RuntimeError("an angle's cos and sin rows must follow its own (`put_angle`)")
R_SX = LANE_LAYOUT["sx_fl"]
R_VR = LANE_LAYOUT["vr_fl"]
R_KSLIP = LANE_LAYOUT["kinematic_slip_fl"]
R_WCOS = LANE_LAYOUT["wheel_cos_fl"]
R_WSIN = LANE_LAYOUT["wheel_sin_fl"]
R_NAX = LANE_LAYOUT["newton_ax_m_s2"]
R_NAY = LANE_LAYOUT["newton_ay_m_s2"]
R_NDONE = LANE_LAYOUT["newton_done"]
R_NR1 = LANE_LAYOUT["newton_r_ax_m_s2"]
R_NR2 = LANE_LAYOUT["newton_r_ay_m_s2"]
R_SY = LANE_LAYOUT["slip_lateral_fl"]
R_SN = LANE_LAYOUT["slip_norm_fl"]
R_MU = LANE_LAYOUT["friction_fl"]
R_CX = LANE_LAYOUT["slip_cos_fl"]
R_NOF = LANE_LAYOUT["no_force_fl"]
R_MF_DFX = LANE_LAYOUT["mf_dfx_dfz_fl"]
R_MF_DFY = LANE_LAYOUT["mf_dfy_dfz_fl"]
R_LAX = LANE_LAYOUT["load_ax_m_s2"]
R_LAY = LANE_LAYOUT["load_ay_m_s2"]
R_LIT = LANE_LAYOUT["load_iteration"]
R_FXW = LANE_LAYOUT["fx_wheel_n_fl"]
R_FXB = LANE_LAYOUT["fx_body_n_fl"]
R_FYB = LANE_LAYOUT["fy_body_n_fl"]
R_STRAIGHT = LANE_LAYOUT["straight_stage"]
N_ROWS = len(LANE_LAYOUT)

CONSTANTS_LAYOUT = Layout(
    "abs-vehicle kernel constants (`abs_vehicle_lane.constants`, one tuple)",
    (
        Slot("mass_kg", "kg"),
        *_per_wheel("static_load_n", "N"),
        *_per_wheel("load_per_ax", "N/(m/s^2)"),
        *_per_wheel("load_per_ay", "N/(m/s^2)"),
        *_per_wheel("x_m", "m"),
        *_per_wheel("y_m", "m"),
        Slot("wheel_radius_m", "m"),
        Slot("min_speed_m_s", "m/s"),
        *_per_wheel("brake_gain", "N m/preset unit", "the wheel's (`wheel_brake_gain`)"),
        Slot("n_filter", "rad/s"),
        Slot("actuator_gain", "preset unit/s"),
        Slot("q_max", "preset unit"),
        Slot("heading_gain", "rad/rad"),
        Slot("yaw_rate_gain_s", "s"),
        Slot("max_steer_rad", "rad"),
        Slot("inv_yaw_inertia_kg_m2", "1/(kg m^2)"),
        Slot("inv_wheel_inertia_kg_m2", "1/(kg m^2)"),
        Slot("inv_actuator_tau_s", "1/s"),
        Slot("inv_steer_tau_s", "1/s"),
        Slot("driver", "-"),
        Slot("select_low", "-"),
        Slot("road_kind", "-"),
        Slot("x_jump_global_m", "m"),
        Slot("split_by_road", "-"),
        Slot("split_y_m", "m"),
        Slot("v_stop_m_s", "m/s"),
        Slot("lock_ratio", "-"),
        Slot("hopeless_m", "m"),
        Slot("yaw_window_s", "s"),
        Slot("dt_s", "s"),
        Slot("half_step_s", "s", "dt / 2"),
        Slot("sixth_step_s", "s", "dt / 6"),
        Slot("n_steps", "-", "steps until the timeout"),
        Slot("t_timeout_s", "s", "n_steps dt"),
        Slot("target_gain_column", "-"),
        Slot("gma_gain_column", "-"),
        *(Slot(f"relaxation_length_{w}_m", "m") for w in WHEELS),
        *(Slot(f"lateral_relaxation_length_{w}_m", "m") for w in WHEELS),
    ),
)
"""Slots named as a plant slot hold that slot's value, `inv_` ones its inverse,
`brake_gain_{wheel}` the wheel's brake gain (`wheel_brake_gain`), other `*_{wheel}` ones the
geometry row of that name at the wheel."""
KC_MASS = CONSTANTS_LAYOUT["mass_kg"]
KC_FZ0 = CONSTANTS_LAYOUT["static_load_n_fl"]
KC_A = CONSTANTS_LAYOUT["load_per_ax_fl"]
KC_B = CONSTANTS_LAYOUT["load_per_ay_fl"]
KC_GX = CONSTANTS_LAYOUT["x_m_fl"]
KC_GY = CONSTANTS_LAYOUT["y_m_fl"]
KC_RW = CONSTANTS_LAYOUT["wheel_radius_m"]
KC_VMIN = CONSTANTS_LAYOUT["min_speed_m_s"]
KC_KQ = CONSTANTS_LAYOUT["brake_gain_fl"]
KC_NF = CONSTANTS_LAYOUT["n_filter"]
KC_GAIN = CONSTANTS_LAYOUT["actuator_gain"]
KC_QMAX = CONSTANTS_LAYOUT["q_max"]
KC_KPSI = CONSTANTS_LAYOUT["heading_gain"]
KC_KR = CONSTANTS_LAYOUT["yaw_rate_gain_s"]
KC_DMAX = CONSTANTS_LAYOUT["max_steer_rad"]
KC_INV_IZ = CONSTANTS_LAYOUT["inv_yaw_inertia_kg_m2"]
KC_INV_J = CONSTANTS_LAYOUT["inv_wheel_inertia_kg_m2"]
KC_INV_TAU = CONSTANTS_LAYOUT["inv_actuator_tau_s"]
KC_INV_ST = CONSTANTS_LAYOUT["inv_steer_tau_s"]
KC_DRIVER = CONSTANTS_LAYOUT["driver"]
KC_SELECT_LOW = CONSTANTS_LAYOUT["select_low"]
KC_KIND = CONSTANTS_LAYOUT["road_kind"]
KC_XJUMP = CONSTANTS_LAYOUT["x_jump_global_m"]
KC_SPLIT_ROAD = CONSTANTS_LAYOUT["split_by_road"]
KC_YSPLIT = CONSTANTS_LAYOUT["split_y_m"]
KC_VSTOP = CONSTANTS_LAYOUT["v_stop_m_s"]
KC_LOCK = CONSTANTS_LAYOUT["lock_ratio"]
KC_HOPELESS = CONSTANTS_LAYOUT["hopeless_m"]
KC_WINDOW = CONSTANTS_LAYOUT["yaw_window_s"]
KC_DT = CONSTANTS_LAYOUT["dt_s"]
KC_HS = CONSTANTS_LAYOUT["half_step_s"]
KC_H6 = CONSTANTS_LAYOUT["sixth_step_s"]
KC_NSTEPS = CONSTANTS_LAYOUT["n_steps"]
KC_TTIMEOUT = CONSTANTS_LAYOUT["t_timeout_s"]
KC_TCOL = CONSTANTS_LAYOUT["target_gain_column"]
KC_GCOL = CONSTANTS_LAYOUT["gma_gain_column"]
KC_SIGMA_X = CONSTANTS_LAYOUT["relaxation_length_fl_m"]
KC_SIGMA_Y = CONSTANTS_LAYOUT["lateral_relaxation_length_fl_m"]
