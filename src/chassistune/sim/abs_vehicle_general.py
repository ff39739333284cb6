"""The vehicle's general path (design.md 3.3), for yaw, lateral velocity, steering or an
unloaded wheel: the step of the lanes the vector pass did not commit, on lanes (`general_steps`:
each stage in branch-free vector loops over the lanes, the loads by Newton's method iterated
while a lane's solve has not returned, the others frozen by select, in the operations of
`plants.abs_vehicle.solve_loads`), with the tires' lagged slips where the run has relaxation
lengths (`abs_vehicle_lag`); and a trace row, its loads by `solve_loads` re-evaluated at the
lane's state."""

from __future__ import annotations

import math

import numba

from chassistune._branchfree import add, clip, fmax, mul, select
from chassistune.plants.abs_vehicle import (
    LOAD_TOL_M_S2,
    MAX_LOAD_ITERATIONS,
    solve_loads,
)
from chassistune.sim.abs_vehicle_lag import (
    has_lengths,
    kinematic_slips_back,
    lag_end,
    lag_stage,
    lag_trace,
    lagged,
)
from chassistune.sim.abs_vehicle_lane import (
    NO_REFCOUNT,
    front_gap,
    lane_arrays,
    lane_get,
    lane_put,
    laws_surfaces,
    magic_formula,
    magic_formula_forces,
    put_state,
    state_of,
)
from chassistune.sim.abs_vehicle_layout import (
    KC_A,
    KC_B,
    KC_DT,
    KC_FZ0,
    KC_H6,
    KC_HS,
    KC_MASS,
    KC_QMAX,
    LANES,
    N_STATE,
    P_FRONT_SHARE,
    P_KQ,
    P_MASS,
    P_R,
    P_SIGMA_X,
    P_SIGMA_Y,
    R_AX,
    R_AY,
    R_CX,
    R_DIST,
    R_DONE,
    R_FXB,
    R_FXW,
    R_FYB,
    R_GENERAL,
    R_HEAD,
    R_HEAD_COS,
    R_HEAD_SIN,
    R_ITER,
    R_K4,
    R_KPREV,
    R_KSUM,
    R_LAX,
    R_LAY,
    R_LIT,
    R_MF_DFX,
    R_MF_DFY,
    R_MU,
    R_NAX,
    R_NAY,
    R_NDONE,
    R_NOF,
    R_NR1,
    R_NR2,
    R_SLIP,
    R_SN,
    R_STEER,
    R_STEER_COS,
    R_STEER_SIN,
    R_STRAIGHT,
    R_SURF,
    R_SX,
    R_SY,
    R_TGT,
    R_VR,
    R_WCOS,
    R_WSIN,
    S_DELTA,
    S_PSI,
    S_Q,
    S_VX,
    S_VY,
    S_W,
    S_X,
    S_Y,
    S_YR,
    T_AX,
    T_AY,
    T_DELTA,
    T_DIST,
    T_FX,
    T_FZ,
    T_PSI,
    T_SLIP,
    T_SPEED,
    T_SURF,
    T_TARGET,
    T_TB,
    T_TIME,
    T_VX,
    T_VY,
    T_WV,
    T_X,
    T_Y,
    T_YR,
    VECTOR,
    W_FXW,
    W_FZ,
    W_SLIP,
)
from chassistune.sim.abs_vehicle_step_end import end_step
from chassistune.sim.abs_vehicle_straight import closed_loads, held, stage_rates
from chassistune.sim.abs_vehicle_wheels import (
    combined_force,
    combined_force_derivative,
    combined_slip,
    force_per_load,
    kinematics,
    steered_wheel,
    wheel_brake_gain,
    wheel_speeds,
)
from chassistune.sim.inlined import INDEXING, INLINE, inlined
from chassistune.sim.integrate import rk4_point


@inlined
def lane_start(st, l, live):
    """Lane l at a step's start: whether the general pass steps it (a live lane the vector
    pass did not commit), and its first stage's k_prev, the last step's k4."""
    general = (lane_get(st, R_DONE, l) == 0.0) & (l < live)
    st[R_GENERAL * LANES + l] = select(general, 1.0, 0.0)
    put_state(st, R_KPREV, l, True, state_of(st, R_K4, LANES, l))


@inlined
def angles(st, width, row_k, c):
    """(cos, sin) of the heading and of the steering angle at the point x + c k (k in the rows
    from row_k) of lanes 0 .. width - 1 (`put_angle`), in a scalar loop whose values the vector
    loops read as rows."""
    for l in range(width):
        psi = lane_get(st, S_PSI, l) + c * lane_get(st, row_k + S_PSI, l)
        delta = lane_get(st, S_DELTA, l) + c * lane_get(st, row_k + S_DELTA, l)
        put_angle(st, R_HEAD, l, psi)
        put_angle(st, R_STEER, l, delta)


@numba.njit(**INDEXING)
def put_angle(st, row, l, a):
    """(cos a, sin a) of lane l into rows row + 1 and row + 2, (1, 0) at 0 as `kinematics`, and
    a into row: computed only where row does not hold a already (a step's end is the next
    step's first stage point)."""
    if a == 0.0:
        st[(row + 1) * LANES + l] = 1.0
        st[(row + 2) * LANES + l] = 0.0
    elif a != st[row * LANES + l]:
        st[(row + 1) * LANES + l] = math.cos(a)
        st[(row + 2) * LANES + l] = math.sin(a)
    st[row * LANES + l] = a


@inlined
def steered(st, l, b, w, j, kc):
    """`steered_wheel` of wheel j (spin w, body state b) with lane l's steering rows."""
    cd = lane_get(st, R_STEER_COS, l)
    sd = lane_get(st, R_STEER_SIN, l)
    return steered_wheel(b, w, cd, sd, j, kc)


@inlined
def stage_point(st, l, c):
    """Lane l's stage point x + c k_prev."""
    return rk4_point(state_of(st, 0, LANES, l), c, state_of(st, R_KPREV, LANES, l))


@numba.njit(**INDEXING)
def put_wheel_kinematics(st, l, j, k):
    """Wheel j's (sx, v/|V|, wheel-to-body cos, sin) of `steered_wheel` into its rows."""
    st[(R_SX + j) * LANES + l] = k[0]
    st[(R_VR + j) * LANES + l] = k[1]
    st[(R_WCOS + j) * LANES + l] = k[2]
    st[(R_WSIN + j) * LANES + l] = k[3]


@inlined
def put_loads(st, l, commit, ax, ay, it, fxw, fxb, fyb):
    """A load solve's result into lane l's rows where `commit`."""
    lane_put(st, R_LAX, l, commit, ax)
    lane_put(st, R_LAY, l, commit, ay)
    lane_put(st, R_LIT, l, commit, it)
    put_wheels(st, R_FXW, l, commit, fxw)
    put_wheels(st, R_FXB, l, commit, fxb)
    put_wheels(st, R_FYB, l, commit, fyb)


@numba.njit(**INDEXING)
def put_wheels(st, row, l, commit, v):
    """The four wheels' values v into lane l's rows from `row` on, where `commit`."""
    lane_put(st, row, l, commit, v[0])
    lane_put(st, row + 1, l, commit, v[1])
    lane_put(st, row + 2, l, commit, v[2])
    lane_put(st, row + 3, l, commit, v[3])


@inlined
def stage_start(st, l, c, kc):
    """A stage's start in lane l: the wheels' kinematics at the stage point, and the load solve
    started from the lane's last solution (`solve_loads`) where the general pass steps the lane
    (returned where not), the stage not straight; returns whether the loop may be linear there
    (no lateral slip or steering: `stage_closed`)."""
    y = stage_point(st, l, c)
    b = y[0]
    k0 = steered(st, l, b, y[1][0], 0, kc)
    k1 = steered(st, l, b, y[2][0], 1, kc)
    k2 = steered(st, l, b, y[3][0], 2, kc)
    k3 = steered(st, l, b, y[4][0], 3, kc)
    put_wheel_kinematics(st, l, 0, k0)
    put_wheel_kinematics(st, l, 1, k1)
    put_wheel_kinematics(st, l, 2, k2)
    put_wheel_kinematics(st, l, 3, k3)
    general = lane_get(st, R_GENERAL, l) != 0.0
    st[R_NAX * LANES + l] = lane_get(st, R_AX, l)
    st[R_NAY * LANES + l] = lane_get(st, R_AY, l)
    st[R_NDONE * LANES + l] = select(general, 0.0, 1.0)
    st[R_STRAIGHT * LANES + l] = 0.0
    flat = (k0[1] == 0.0) & (k1[1] == 0.0) & (k2[1] == 0.0) & (k3[1] == 0.0)
    return flat & (k0[3] == 0.0) & (k1[3] == 0.0) & (k2[3] == 0.0) & (k3[3] == 0.0)


@numba.njit(**INDEXING)
def all_zero(st, row, l):
    """Whether the four wheels' values of lane l from row `row` on are all 0 (branch-free)."""
    v = wheel_rows(st, row, l)
    return (v[0] == 0.0) & (v[1] == 0.0) & (v[2] == 0.0) & (v[3] == 0.0)


@inlined
def stage_closed(st, l, c, kc, srf):
    """After `stage_start`, where lane l's loop is linear (no lateral slip or steering, every
    load >= 0): the load solve returned in closed form (`closed_loads`), and whether the stage
    is straight (no yaw, lateral velocity, heading or steering, every load >= 0)."""
    b = stage_point(st, l, c)[0]
    _, s = laws_surfaces(st, l, srf)
    c0 = force_per_load(lane_get(st, R_SX, l), s[0])
    c1 = force_per_load(lane_get(st, R_SX + 1, l), s[1])
    c2 = force_per_load(lane_get(st, R_SX + 2, l), s[2])
    c3 = force_per_load(lane_get(st, R_SX + 3, l), s[3])
    ax, fx, loaded = closed_loads((c0, c1, c2, c3), kc)
    linear = all_zero(st, R_VR, l) & all_zero(st, R_WSIN, l)
    general = lane_get(st, R_GENERAL, l) != 0.0
    st[R_NDONE * LANES + l] = select((linear & loaded) | (not general), 1.0, 0.0)
    put_loads(st, l, True, ax, 0.0, 0.0, fx, fx, (0.0, 0.0, 0.0, 0.0))
    straight = (b[1] == 0.0) & (b[2] == 0.0) & (b[5] == 0.0) & (b[6] == 0.0) & loaded
    st[R_STRAIGHT * LANES + l] = select(straight, 1.0, 0.0)


@numba.njit(**INDEXING)
def wheel_load(st, l, ax, ay, j, s, kc, mf, srf, first):
    """Wheel j's load at (ax, ay) (held >= 0) and its forces (wheel-frame Fx, body-frame Fx,
    Fy); the tire's slip there (`combined_slip`) into its rows, for `wheel_load_derivative`, or
    with the Magic Formula tire (`mf`), at the solve's `first` iterate only, its forces' load
    derivative (`vehicle_mf.wheel_forces_and_derivative`): the later iterations keep that
    Jacobian (a chord method: the iterate stops on the same exact residual)."""
    z = fmax(kc[KC_FZ0 + j] + kc[KC_A + j] * ax + kc[KC_B + j] * ay, 0.0)
    sx = lane_get(st, R_SX + j, l)
    vr = lane_get(st, R_VR + j, l)
    if mf:
        b = lane_get(st, R_SURF + j, l)
        fx, fy, dfx, dfy = magic_formula_forces(srf, b, j, sx, vr, z, first)
        if first:
            st[(R_MF_DFX + j) * LANES + l] = dfx
            st[(R_MF_DFY + j) * LANES + l] = dfy
    else:
        sy, sn, mu, cx, cy, none = combined_slip(sx, vr, z, s)
        fx, fy = combined_force(z, mu, cx, cy, none)
        st[(R_SY + j) * LANES + l] = sy
        st[(R_SN + j) * LANES + l] = sn
        st[(R_MU + j) * LANES + l] = mu
        st[(R_CX + j) * LANES + l] = cx
        st[(R_NOF + j) * LANES + l] = select(none, 1.0, 0.0)
    cs = lane_get(st, R_WCOS + j, l)
    sn = lane_get(st, R_WSIN + j, l)
    return fx, cs * fx - sn * fy, sn * fx + cs * fy


@numba.njit(**INDEXING)
def wheel_load_derivative(st, l, j, s, mf):
    """Wheel j's body-frame (dFx/dFz, dFy/dFz) at the slip `wheel_load` left in its rows (the
    Magic Formula tire's: the derivatives it left there)."""
    if mf:
        dfx = lane_get(st, R_MF_DFX + j, l)
        dfy = lane_get(st, R_MF_DFY + j, l)
    else:
        dfx, dfy = combined_force_derivative(
            lane_get(st, R_SX + j, l),
            lane_get(st, R_SY + j, l),
            lane_get(st, R_SN + j, l),
            lane_get(st, R_MU + j, l),
            lane_get(st, R_CX + j, l),
            lane_get(st, R_NOF + j, l) != 0.0,
            s,
        )
    cs = lane_get(st, R_WCOS + j, l)
    sn = lane_get(st, R_WSIN + j, l)
    return cs * dfx - sn * dfy, sn * dfx + cs * dfy


@inlined
def wheel_sum(a0, a1, a2, a3):
    """0 + a0 + a1 + a2 + a3 in that order (a sum over the wheels as a loop adds it)."""
    total = 0.0
    total += a0
    total += a1
    total += a2
    total += a3
    return total


@inlined
def load_residual(st, l, it, kc, srf, mf):
    """Iteration `it` of lane l's load solve by Newton's method on (ax, ay) (`solve_loads`,
    the same operations), where it has not returned: the forces at the iterate, then the
    return where the residual is within LOAD_TOL_M_S2 or at the last iteration. Returns
    whether the solve goes on (`load_step` then takes its step)."""
    ax = lane_get(st, R_NAX, l)
    ay = lane_get(st, R_NAY, l)
    _, s = laws_surfaces(st, l, srf)
    f0 = wheel_load(st, l, ax, ay, 0, s[0], kc, mf, srf, it == 0)
    f1 = wheel_load(st, l, ax, ay, 1, s[1], kc, mf, srf, it == 0)
    f2 = wheel_load(st, l, ax, ay, 2, s[2], kc, mf, srf, it == 0)
    f3 = wheel_load(st, l, ax, ay, 3, s[3], kc, mf, srf, it == 0)
    sfx = wheel_sum(f0[1], f1[1], f2[1], f3[1])
    sfy = wheel_sum(f0[2], f1[2], f2[2], f3[2])
    mass = kc[KC_MASS]
    r1 = sfx / mass - ax
    r2 = sfy / mass - ay
    pending = lane_get(st, R_NDONE, l) == 0.0
    done = (abs(r1) + abs(r2) <= LOAD_TOL_M_S2) | (it >= MAX_LOAD_ITERATIONS)
    put_loads(
        st,
        l,
        pending & done,
        sfx / mass,
        sfy / mass,
        float(it),
        (f0[0], f1[0], f2[0], f3[0]),
        (f0[1], f1[1], f2[1], f3[1]),
        (f0[2], f1[2], f2[2], f3[2]),
    )
    lane_put(st, R_NDONE, l, pending & done, 1.0)
    st[R_NR1 * LANES + l] = r1
    st[R_NR2 * LANES + l] = r2
    return pending & (not done)


@inlined
def load_step(st, l, it, kc, srf, mf):
    """The step of iteration `it` of lane l's load solve where it goes on (`solve_loads`, the
    same operations): Newton's, fixed-point after MAX_LOAD_ITERATIONS // 2 or at a singular
    Jacobian, from the residual and the tire's slip `load_residual` left in the rows."""
    _, s = laws_surfaces(st, l, srf)
    d0 = wheel_load_derivative(st, l, 0, s[0], mf)
    d1 = wheel_load_derivative(st, l, 1, s[1], mf)
    d2 = wheel_load_derivative(st, l, 2, s[2], mf)
    d3 = wheel_load_derivative(st, l, 3, s[3], mf)
    j11 = wheel_sum(
        d0[0] * kc[KC_A], d1[0] * kc[KC_A + 1], d2[0] * kc[KC_A + 2], d3[0] * kc[KC_A + 3]
    )
    j12 = wheel_sum(
        d0[0] * kc[KC_B], d1[0] * kc[KC_B + 1], d2[0] * kc[KC_B + 2], d3[0] * kc[KC_B + 3]
    )
    j21 = wheel_sum(
        d0[1] * kc[KC_A], d1[1] * kc[KC_A + 1], d2[1] * kc[KC_A + 2], d3[1] * kc[KC_A + 3]
    )
    j22 = wheel_sum(
        d0[1] * kc[KC_B], d1[1] * kc[KC_B + 1], d2[1] * kc[KC_B + 2], d3[1] * kc[KC_B + 3]
    )
    mass = kc[KC_MASS]
    r1 = lane_get(st, R_NR1, l)
    r2 = lane_get(st, R_NR2, l)
    a11 = j11 / mass - 1.0
    a12 = j12 / mass
    a21 = j21 / mass
    a22 = j22 / mass - 1.0
    det = a11 * a22 - a12 * a21
    newton = (it < MAX_LOAD_ITERATIONS // 2) & (det != 0.0)
    going = lane_get(st, R_NDONE, l) == 0.0
    ax = lane_get(st, R_NAX, l)
    ay = lane_get(st, R_NAY, l)
    lane_put(st, R_NAX, l, going, ax + select(newton, (-r1 * a22 + r2 * a12) / det, r1))
    lane_put(st, R_NAY, l, going, ay + select(newton, (-r2 * a11 + r1 * a21) / det, r2))


@inlined
def load_solve(st, blocks, kc, srf, mf):
    """The lanes' load solves of a stage (`load_residual`, `load_step`) until each has returned,
    with the Magic Formula tire or not (`mf`: a constant at each call, so that LLVM drops the
    other tire's code from the bilinear tire's vector loops)."""
    for it in range(MAX_LOAD_ITERATIONS + 1):
        going = False
        for blk in range(blocks):
            if solving(st, blk):
                for j in range(VECTOR):
                    going |= load_residual(st, blk * VECTOR + j, it, kc, srf, mf)
        if not going:
            return
        for blk in range(blocks):
            if solving(st, blk):
                for j in range(VECTOR):
                    load_step(st, blk * VECTOR + j, it, kc, srf, mf)


@numba.njit(**NO_REFCOUNT)
def magic_formula_load_solve(st, blocks, kc, srf):
    """`load_solve` with the Magic Formula tire, a function of its own: its loops call the
    tire's forces (`vehicle_mf.wheel_forces`) and stay scalar, apart from the bilinear tire's
    vector loops."""
    load_solve(st, blocks, kc, srf, True)


@inlined
def solving(st, blk):
    """Whether a lane of vector `blk` has a load solve that has not returned."""
    pending = False
    for j in range(VECTOR):
        pending |= lane_get(st, R_NDONE, blk * VECTOR + j) == 0.0
    return pending


@numba.njit(**INLINE)
def stage_end(form, st, l, c, first, weight, kc, srf, ctrl):
    """A stage's end in lane l: its derivatives from the solved loads (`stage_rates`, the laws'
    continuous form of key `form`, controller vector ctrl) become
    k_prev and enter the RK4 sum (weight 2 for stages 2 and 3); the load solve's result
    becomes the next one's start where the stage was not straight."""
    y = stage_point(st, l, c)
    b = y[0]
    g, s = laws_surfaces(st, l, srf)
    e = (
        s[0][4] - clip(lane_get(st, R_SX, l), 0.0, 1.0),
        s[1][4] - clip(lane_get(st, R_SX + 1, l), 0.0, 1.0),
        s[2][4] - clip(lane_get(st, R_SX + 2, l), 0.0, 1.0),
        s[3][4] - clip(lane_get(st, R_SX + 3, l), 0.0, 1.0),
    )
    vx = b[0]
    vy = b[1]
    turned = b[5] != 0.0
    cp = lane_get(st, R_HEAD_COS, l)
    sp = lane_get(st, R_HEAD_SIN, l)
    dxy = (select(turned, vx * cp - vy * sp, vx), select(turned, vx * sp + vy * cp, vy))
    k = stage_rates(
        form,
        y,
        lane_get(st, R_LAX, l),
        lane_get(st, R_LAY, l),
        wheel_rows(st, R_FXB, l),
        wheel_rows(st, R_FYB, l),
        wheel_rows(st, R_FXW, l),
        e,
        dxy,
        g,
        ctrl,
        kc,
    )
    total = state_of(st, R_KSUM, LANES, l)
    put_state(st, R_KPREV, l, True, k)
    put_state(st, R_KSUM, l, first, k)
    put_state(st, R_KSUM, l, not first, add(total, mul(weight, k)))
    solved = (lane_get(st, R_GENERAL, l) != 0.0) & (lane_get(st, R_STRAIGHT, l) == 0.0)
    lane_put(st, R_AX, l, solved, lane_get(st, R_LAX, l))
    lane_put(st, R_AY, l, solved, lane_get(st, R_LAY, l))
    lane_put(st, R_ITER, l, solved, fmax(lane_get(st, R_ITER, l), lane_get(st, R_LIT, l)))


@numba.njit(**INDEXING)
def wheel_rows(st, row, l):
    """The four wheels' values of lane l from row `row` on."""
    return (
        lane_get(st, row, l),
        lane_get(st, row + 1, l),
        lane_get(st, row + 2, l),
        lane_get(st, row + 3, l),
    )


@inlined
def general_end(st, l, kc):
    """The RK4 update of lane l from its sum, the step-end limits and kinematics, and the step's
    end (`end_step`, the stop included) where the general pass steps the lane; returns whether
    its run ended there."""
    x = state_of(st, 0, LANES, l)
    xn = held(
        add(x, mul(kc[KC_H6], state_of(st, R_KSUM, LANES, l))), kc[KC_QMAX], front_gap(st, l, kc)
    )
    _, _, _, _, va0, sl0 = steered(st, l, xn[0], xn[1][0], 0, kc)
    _, _, _, _, va1, sl1 = steered(st, l, xn[0], xn[2][0], 1, kc)
    _, _, _, _, va2, sl2 = steered(st, l, xn[0], xn[3][0], 2, kc)
    _, _, _, _, va3, sl3 = steered(st, l, xn[0], xn[4][0], 3, kc)
    general = lane_get(st, R_GENERAL, l) != 0.0
    ended = end_step(
        st,
        l,
        general,
        x,
        wheel_speeds(x, kc),
        xn,
        (sl0, sl1, sl2, sl3),
        (va0, va1, va2, va3),
        lane_get(st, R_HEAD_COS, l),
        lane_get(st, R_HEAD_SIN, l),
        state_of(st, R_KPREV, LANES, l),
        kc,
        True,
    )
    return ended & general


@numba.njit(**NO_REFCOUNT)
def general_steps(form, args):
    """One RK4 step, args = (st, width, kc, srf, ctrl, live), with the laws' continuous form of
    key `form` (a literal: compiled once per form), of the live lanes among 0 .. width - 1
    (whole vectors) that the vector pass did not commit (split-mu, a driver steering, an
    unloaded wheel, the step of a stop), in the general case, all lanes at once: each stage's
    kinematics and closed-form loads, the Newton load solve iterated while a lane's has not
    returned (the others frozen by select; each iteration's forces and residual in one loop,
    its step in a second run only while a lane goes on: the last iteration computes no
    Jacobian), the stage's derivatives (`stage_rates`, as the straight pass); then the step's
    end. Straight-line stages give the straight pass's numbers (they leave the load guess as it
    was). Returns 1 if a run ended."""
    numba.literally(form)
    st, width, kc, srf, ctrl, live = args
    mf = magic_formula(srf)  # no closed-form loads: the force is not linear in the load
    relaxed = lagged(kc)  # the tires read lagged slips (`abs_vehicle_lag`)
    blocks = width // VECTOR
    for blk in range(blocks):
        for j in range(VECTOR):
            lane_start(st, blk * VECTOR + j, live)
    for stage in range(4):
        c = 0.0 if stage == 0 else (kc[KC_DT] if stage == 3 else kc[KC_HS])
        weight = 1.0 if stage == 3 else 2.0
        angles(st, width, R_KPREV, c)
        if relaxed:
            lagged_stage_start(st, blocks, c, stage == 0, weight, kc, srf)
        else:
            for blk in range(blocks):
                linear = False
                for j in range(VECTOR):
                    linear |= stage_start(st, blk * VECTOR + j, c, kc)
                if linear and not mf:
                    for j in range(VECTOR):
                        stage_closed(st, blk * VECTOR + j, c, kc, srf)
        if mf:
            magic_formula_load_solve(st, blocks, kc, srf)
        else:
            load_solve(st, blocks, kc, srf, False)
        if relaxed:
            kinematic_slips_back(st, blocks)
        for blk in range(blocks):
            for j in range(VECTOR):
                stage_end(form, st, blk * VECTOR + j, c, stage == 0, weight, kc, srf, ctrl)
    angles(st, width, R_KSUM, kc[KC_H6])
    if relaxed:
        lag_end(st, blocks, kc)
    ended = False
    for blk in range(blocks):
        for j in range(VECTOR):
            ended |= general_end(st, blk * VECTOR + j, kc)
    return ended


@numba.njit(**NO_REFCOUNT)
def lagged_stage_start(st, blocks, c, first, weight, kc, srf):
    """A stage's start in the lanes of `blocks` vectors where the tires read lagged slips: the
    wheels' kinematics (`stage_start`), the lag (`abs_vehicle_lag.lag_stage`: the tire's slips in
    the rows the load solve reads) and, with the bilinear tire, the loads in closed form where
    the lagged slips are linear (`stage_closed`)."""
    mf = magic_formula(srf)
    for blk in range(blocks):
        for j in range(VECTOR):
            stage_start(st, blk * VECTOR + j, c, kc)
        for j in range(VECTOR):
            lag_stage(st, blk * VECTOR + j, c, first, weight, kc)
        if not mf:
            for j in range(VECTOR):
                stage_closed(st, blk * VECTOR + j, c, kc, srf)


@numba.njit(**NO_REFCOUNT)
def trace_row(trace_row, start, t, st, l, work):
    """Trace row `trace_row` of lane l, work = (p, geo, surfs, sidx, guess, sc, y, wbuf): its
    state, and the wheels' kinematics, loads and forces re-evaluated at it (`kinematics`,
    `solve_loads` from the lane's last solution) on scratch copies of the lane's arrays (tracing
    does not change the run); the start row (`start`) takes the slips of that evaluation."""
    p, geo, surfs, sidx, guess, sc, y, wbuf = work
    for s in range(N_STATE):
        y[s] = lane_get(st, s, l)
    lane_arrays(st, l, sidx, guess)
    for j in range(4):
        wbuf[j] = y[S_W + j]
    kinematics(y[S_VX], y[S_VY], y[S_YR], y[S_DELTA], wbuf, p, geo, sc)
    if has_lengths(p, P_SIGMA_X, P_SIGMA_Y):
        lag_trace(trace_row, st, l, p, sc)
    guess[0, 0], guess[1, 0], _ = solve_loads(
        sc, surfs, sidx, 0, geo, p[P_MASS], guess[0, 0], guess[1, 0]
    )
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
    trace_row[T_DIST] = lane_get(st, R_DIST, l)
    for j in range(4):
        trace_row[T_WV + j] = y[S_W + j] * p[P_R]
        trace_row[T_SLIP + j] = lane_get(st, R_SLIP + j, l) if not start else sc[W_SLIP, j]
        trace_row[T_TARGET + j] = lane_get(st, R_TGT + sidx[j, 0], l)
        trace_row[T_FZ + j] = sc[W_FZ, j]
        trace_row[T_TB + j] = wheel_brake_gain(p[P_KQ], p[P_FRONT_SHARE], j) * y[S_Q + j]
        trace_row[T_FX + j] = sc[W_FXW, j]
        trace_row[T_SURF + j] = sidx[j, 0]
