"""The four wheels of the vehicle (design.md 3.3): their kinematics (wheel-frame velocity, slip
over |V|), the bilinear tire in straight-line braking (`abs_wheel_tires.tire_law_mu`), the
wheel, actuator and PID rates (the single wheel's, `abs_wheel_model.wheel_rates`), select-low on
the rear channels and the surface under each wheel. Scalar and branch-free where the vector
loop reads them (inlined by LLVM: `sim.inlined`)."""

from __future__ import annotations

import math

import numba

from chassistune._branchfree import clip, fmax, fmin, select
from chassistune.controllers.laws.dispatch import law_rate
from chassistune.plants.vehicle_roads import ROAD_MU_JUMP, ROAD_SPLIT
from chassistune.sim.abs_vehicle_layout import (
    G_X,
    G_Y,
    KC_GX,
    KC_GY,
    KC_KIND,
    KC_RW,
    KC_SPLIT_ROAD,
    KC_VMIN,
    KC_XJUMP,
    KC_YSPLIT,
    P_R,
    P_VMIN,
    W_CS,
    W_SLIP,
    W_SN,
    W_SX,
    W_VABS,
    W_VR,
)
from chassistune.sim.abs_wheel_model import wheel_rates
from chassistune.sim.abs_wheel_tires import KIND_BILINEAR, tire_law_mu
from chassistune.sim.inlined import INLINE, inlined


@inlined
def wheel_kinematics(uw, vw, w, r_w, vmin):
    """(sx, v/|V|, |V|, clipped slip) of a wheel with wheel-frame velocity (uw, vw)."""
    vabs = fmax(math.sqrt(uw * uw + vw * vw), vmin)
    inv = 1.0 / vabs
    sx = (uw - w * r_w) * inv
    return sx, vw * inv, vabs, clip(sx, 0.0, 1.0)


@inlined
def kinematics(vx, vy, r, delta, w, p, geo, sc):
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
        sx, vr, vabs, slip = wheel_kinematics(uw, vw, w[j], p[P_R], p[P_VMIN])
        sc[W_SX, j] = sx
        sc[W_VR, j] = vr
        sc[W_VABS, j] = vabs
        sc[W_SLIP, j] = slip


@inlined
def wheel_velocity(b, cd, sd, j, kc):
    """The velocity (u, v) of wheel j's centre in the wheel's frame at body state b = (vx, vy,
    r, ...), the steering angle given as its (cos, sin) = (cd, sd) (1, 0 at 0), and whether the
    wheel is turned (a front wheel where sd != 0). Branch-free."""
    vx = b[0]
    vy = b[1]
    r = b[2]
    u = vx - r * kc[KC_GY + j]
    v = vy + r * kc[KC_GX + j]
    turned = (j < 2) & (sd != 0.0)
    return select(turned, cd * u + sd * v, u), select(turned, cd * v - sd * u, v), turned


@inlined
def steered_wheel(b, w, cd, sd, j, kc):
    """`kinematics` of wheel j (spin w) at body state b, the steering angle given as its
    (cos, sin) = (cd, sd) (1, 0 at 0): (sx, v/|V|, wheel-to-body (cos, sin), |V|, clipped
    slip), a front wheel turned where sd != 0. Branch-free."""
    uw, vw, turned = wheel_velocity(b, cd, sd, j, kc)
    sx, vr, vabs, slip = wheel_kinematics(uw, vw, w, kc[KC_RW], kc[KC_VMIN])
    return sx, vr, select(turned, cd, 1.0), select(turned, sd, 0.0), vabs, slip


@inlined
def unsteered(b, wt, j, kc):
    """(|V|, clipped slip) of wheel j (state wt) unsteered, body b: `kinematics` with delta 0."""
    _, _, _, _, vabs, slip = steered_wheel(b, wt[0], 1.0, 0.0, j, kc)
    return vabs, slip


@inlined
def wheel_speeds(x, kc):
    """The four wheels' |V| at state x (unsteered: steering turns a wheel's velocity, not its
    norm)."""
    b = x[0]
    return (
        unsteered(b, x[1], 0, kc)[0],
        unsteered(b, x[2], 1, kc)[0],
        unsteered(b, x[3], 2, kc)[0],
        unsteered(b, x[4], 3, kc)[0],
    )


@inlined
def select_low(e2, e3, on):
    """The rear channels' slip errors from the rear wheels' (e2, e3): with select-low (`on`)
    both get min(e2, e3), the error of the wheel with the larger slip, else each its own; and
    whether select-low took wheel rr's. Branch-free."""
    low = e3 < e2
    return select(on & low, e3, e2), select(on & (not low), e2, e3), on & low


@inlined
def wheel_brake_gain(kq, front_share, j):
    """Brake torque per unit pressure of wheel j (0, 1 front; 2, 3 rear) with the front axle's
    share s of the torque at equal pressure (design.md 3.3): 2 s kq in front, 2 (1 - s) kq
    behind, so the front over the rear is s / (1 - s); s = 0.5 gives every wheel kq exactly."""
    return 2.0 * select(j < 2, front_share, 1.0 - front_share) * kq


@numba.njit(**INLINE)
def wheel_law_rates(form, w, q, qr, x, e, fxw, held, c, r_w, kq, inv_j, nf, gain, inv_tau, q_max):
    """Rates (dw, dq, dqr, dx) of a wheel's spin, brake actuator and law state x (design.md
    3.1): the single wheel's equations (`abs_wheel_model.wheel_rates`, its tire force -fxw: the
    wheel-frame force Fx acts against the travel) under the command u of the law's continuous
    form of key `form` (`dispatch.law_rate`: the PID u = u0 + kp e + ki z + kd N (e - xf) with
    conditional integration for the held PID) with the held values (u0, kp, ki, kd) and the
    controller vector c. Branch-free."""
    u, dx = law_rate(form, e, x, held, c, nf, q >= q_max, q <= 0.0)
    _, dw, dq, dqr, _, _ = wheel_rates(w, q, qr, -fxw, u, r_w, 0.0, inv_j, kq, gain, inv_tau, q_max)
    return dw, dq, dqr, dx


@inlined
def straight_wheel(vx, w, s, r_w, vmin):
    """Force per unit load and clipped slip of a wheel on surface s in straight-line braking
    (r = vy = 0, no steering): `kinematics` and `straight_force_per_load` in that case, bit for
    bit."""
    vabs = fmax(math.sqrt(vx * vx), vmin)
    sx = (vx - w * r_w) * (1.0 / vabs)
    return force_per_load(sx, s), clip(sx, 0.0, 1.0)


@inlined
def bilinear(s, surface):
    """mu(s) of the bilinear curve of `surface` (design.md 3.2)."""
    c = surface
    return tire_law_mu(KIND_BILINEAR, s, c[0], c[1], c[2], c[3], c, c, c)  # no table


@inlined
def force_per_load(sx, s):
    """Fx / Fz of a wheel without lateral slip on surface s: -mu(min(|sx|, 1)) sign(sx), 0 at
    sx = 0 (`plants.abs_vehicle.straight_force_per_load`, bit for bit)."""
    a = abs(sx)
    return select(a > 0.0, -math.copysign(bilinear(fmin(a, 1.0), s), sx), 0.0)


@inlined
def combined_slip(sx, vr, fz, s):
    """The combined slip of a wheel with load fz on surface s (design.md 3.3), as
    `plants.abs_vehicle.tire_force` computes it: (sy, |s|, mu(min(|s|, 1)), the slip's direction
    (sx, sy) / |s|, and whether the wheel has no force: fz <= 0 or s = 0). Branch-free."""
    sy = vr * s[5] / fz
    sn = math.sqrt(sx * sx + sy * sy)
    mu = bilinear(fmin(sn, 1.0), s)
    return sy, sn, mu, sx / sn, sy / sn, (fz <= 0.0) | (sn == 0.0)


@inlined
def combined_force(fz, mu, cx, cy, none):
    """(Fx, Fy) of a wheel in its own frame from its `combined_slip` (load fz, friction mu,
    slip direction (cx, cy)): `plants.abs_vehicle.tire_force` bit for bit, 0 where `none`."""
    f = fz * mu
    return select(none, 0.0, -f * cx), select(none, 0.0, -f * cy)


@inlined
def combined_force_derivative(sx, sy, sn, mu, cx, none, s):
    """(dFx/dFz, dFy/dFz) of a wheel in its own frame on surface s from its `combined_slip`:
    `plants.abs_vehicle.tire_force` bit for bit, 0 where `none`."""
    dmu = select(fmin(sn, 1.0) <= s[0], s[1], select(sn < 1.0, -s[3], 0.0))
    # F = -Fz phi(s) (sx, sy) with phi = mu/s and sy ~ 1/Fz: differentiate in Fz
    t = (dmu * sn - mu) / (sn * sn) * sy * sy / sn
    return select(none, 0.0, -mu * cx + t * sx), select(none, 0.0, t * sy)


@inlined
def surface_flag(b_old, x, y, cp, sp, j, kc):
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
