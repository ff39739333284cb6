"""Quarter-car active suspension (design.md 3.4; Jing and Xu 2023, `iabc-suspension`): the
closed-loop state-space model with a linear controller (parameters and presets:
`plants.quarter_car_params`).

Plant (`iabc-suspension` eqs. 1-3 in the corrected form of design.md 3.4)::

    ms zs'' = -ks (zs - zu) - cs (zs' - zu') + u
    mu zu'' =  ks (zs - zu) + cs (zs' - zu') - kt (zu - z0) - u
    z0'     = -2 pi f0 z0 + b w,    b = 2 pi n0 sqrt(Gq v),  w white with intensity W = 1/2

Controller: PID on e = 0 - y with a filtered derivative,
``u = kp e + ki int(e) + kd N (e - xf)``, ``xf' = N (e - xf)`` (so ``kd N s/(s + N)`` acts on e),
y selected by `feedback`. Passive is the PID with zero gains, skyhook is kp = c_sky on velocity.

Two realizations come out of one builder (`closed_loop`):

- *minimal* (the Lyapunov objective): the integral of body velocity is -zs and that of body
  acceleration is -vs, so no integrator state is added for them (it would put an eigenvalue at
  exactly 0 and make the Lyapunov equation singular); the integrator of displacement or travel is
  kept only when ki != 0 and the derivative filter only when kd != 0.
- *explicit* (the simulation): an integrator state and a filter state always, as a block diagram
  would have them; 7 states for every candidate.

Body acceleration feedback is an algebraic loop (y depends on u); it is solved exactly.
States: zs, vs, zu, vu, z0, [I = int(e)], [xf]. Outputs: the rows of OUT_* below.
"""

from __future__ import annotations

import numpy as np
from numba import njit

PLANT_SLOTS: tuple[tuple[str, str, str], ...] = (
    ("sprung_mass_kg", "kg", "ms"),
    ("unsprung_mass_kg", "kg", "mu"),
    ("spring_n_m", "N/m", "ks"),
    ("damper_n_s_m", "N s/m", "cs"),
    ("tire_stiffness_n_m", "N/m", "kt"),
    ("road_pole_rad_s", "rad/s", "2 pi f0 of the road filter"),
    ("road_gain", "m/s^0.5", "b of the road filter"),
)
"""The plant vector read by `closed_loop`: (name, unit, meaning), in order (the kernels' Layout)."""


def _positions(slots: tuple[tuple[str, str, str], ...], *names: str) -> tuple[int, ...]:
    """The positions of `names` among the slots' names."""
    order = [name for name, _, _ in slots]
    return tuple(order.index(n) for n in names)


P_MS, P_MU, P_KS, P_CS, P_KT, P_LAM, P_B = _positions(
    PLANT_SLOTS,
    "sprung_mass_kg",
    "unsprung_mass_kg",
    "spring_n_m",
    "damper_n_s_m",
    "tire_stiffness_n_m",
    "road_pole_rad_s",
    "road_gain",
)
N_PLANT = len(PLANT_SLOTS)

# feedback signal codes
FB_DISPLACEMENT, FB_VELOCITY, FB_ACCELERATION, FB_TRAVEL = range(4)
FEEDBACK_CODES = {
    "body_displacement": FB_DISPLACEMENT,
    "body_velocity": FB_VELOCITY,
    "body_acceleration": FB_ACCELERATION,
    "suspension_travel": FB_TRAVEL,
}

# state indices (the controller states follow the plant's when present)
S_ZS, S_VS, S_ZU, S_VU, S_Z0 = range(5)
N_PLANT_STATES = 5
MAX_STATES = 7

OUTPUT_SLOTS: tuple[tuple[str, str, str], ...] = (
    ("body_acc", "m/s^2", "body vertical acceleration zs''"),
    ("susp_travel", "m", "suspension travel zs - zu"),
    ("tire_defl", "m", "tire deflection zu - z0"),
    ("force", "N", "actuator force u"),
    ("road", "m", "road displacement z0"),
    ("body_disp", "m", "body displacement zs"),
)
"""The rows of C (outputs y = C x): (name, unit, meaning), in order (the kernels' Layout)."""
OUT_ACC, OUT_TRAVEL, OUT_TIRE, OUT_FORCE, OUT_ROAD, OUT_ZS = _positions(
    OUTPUT_SLOTS, "body_acc", "susp_travel", "tire_defl", "force", "road", "body_disp"
)
N_OUT = len(OUTPUT_SLOTS)

# closed_loop() status
SINGULAR_LOOP = -1


@njit(cache=True, nogil=True)
def closed_loop(
    plant: np.ndarray,
    feedback: int,
    kp: float,
    ki: float,
    kd: float,
    n_filter: float,
    explicit: bool,
    a: np.ndarray,
    b: np.ndarray,
    c: np.ndarray,
) -> int:
    """Fill a[:m, :m], b[:m], c[:, :m] with the closed loop; return m (SINGULAR_LOOP if none).

    `a` is (MAX_STATES, MAX_STATES), `b` (MAX_STATES,), `c` (N_OUT, MAX_STATES); entries beyond
    m are zeroed. With acceleration feedback the loop u = K x needs 1 + (kp + kd N)/ms > 0.
    """
    ms = plant[P_MS]
    mu = plant[P_MU]
    ks = plant[P_KS]
    cs = plant[P_CS]
    kt = plant[P_KT]
    integral_state = explicit or (feedback in (FB_DISPLACEMENT, FB_TRAVEL) and ki != 0.0)
    filter_state = explicit or kd != 0.0
    m = N_PLANT_STATES
    i_int = -1
    i_flt = -1
    if integral_state:
        i_int = m
        m += 1
    if filter_state:
        i_flt = m
        m += 1
    a[:, :] = 0.0
    b[:] = 0.0
    c[:, :] = 0.0

    # suspension force on the body, Fs = -ks (zs - zu) - cs (vs - vu), as a row over the states
    fs = np.zeros(m)
    fs[S_ZS] = -ks
    fs[S_ZU] = ks
    fs[S_VS] = -cs
    fs[S_VU] = cs

    # measured signal y = cy x + dy u
    cy = np.zeros(m)
    dy = 0.0
    if feedback == FB_DISPLACEMENT:
        cy[S_ZS] = 1.0
    elif feedback == FB_VELOCITY:
        cy[S_VS] = 1.0
    elif feedback == FB_ACCELERATION:
        cy[:] = fs / ms
        dy = 1.0 / ms
    else:
        cy[S_ZS] = 1.0
        cy[S_ZU] = -1.0

    # int(e) as a row over the states: its own state, or -zs / -vs in the minimal realization
    r_int = np.zeros(m)
    if integral_state:
        r_int[i_int] = 1.0
    elif feedback == FB_VELOCITY:
        r_int[S_ZS] = -1.0
    elif feedback == FB_ACCELERATION:
        r_int[S_VS] = -1.0

    # u = -(kp + kd N) (cy x + dy u) + ki int(e) - kd N xf  =>  u = K x
    g = kp + kd * n_filter if filter_state else kp
    den = 1.0 + g * dy
    if not den > 0.0:
        return SINGULAR_LOOP
    k = (-g * cy + ki * r_int) / den
    if filter_state:
        k[i_flt] -= kd * n_filter / den
    e_row = -(cy + dy * k)

    a[S_ZS, S_VS] = 1.0
    a[S_VS, :m] = (fs + k) / ms
    a[S_ZU, S_VU] = 1.0
    a[S_VU, :m] = (-fs - k) / mu
    a[S_VU, S_ZU] -= kt / mu
    a[S_VU, S_Z0] += kt / mu
    a[S_Z0, S_Z0] = -plant[P_LAM]
    if integral_state:
        a[i_int, :m] = e_row
    if filter_state:
        a[i_flt, :m] = n_filter * e_row
        a[i_flt, i_flt] -= n_filter
    b[S_Z0] = plant[P_B]

    c[OUT_ACC, :m] = a[S_VS, :m]
    c[OUT_TRAVEL, S_ZS] = 1.0
    c[OUT_TRAVEL, S_ZU] = -1.0
    c[OUT_TIRE, S_ZU] = 1.0
    c[OUT_TIRE, S_Z0] = -1.0
    c[OUT_FORCE, :m] = k
    c[OUT_ROAD, S_Z0] = 1.0
    c[OUT_ZS, S_ZS] = 1.0
    return m


def frequency_response(
    plant: np.ndarray,
    feedback: int,
    kp: float,
    ki: float,
    kd: float,
    n_filter: float,
    omega: np.ndarray,
) -> dict[str, np.ndarray]:
    """Responses per unit road displacement Z0(s) at s = j omega, from the Laplace-domain equations.

    Written from the equations of motion, not from `closed_loop`, so that it checks the state
    space: with C(s) = kp + ki/s + kd N s/(s + N) and Y = h_s Zs + h_u Zu,

        [ms s^2 + ks + cs s + C h_s ] Zs + [-(ks + cs s) + C h_u]        Zu = 0
        [-(ks + cs s) - C h_s       ] Zs + [mu s^2 + ks + cs s + kt - C h_u] Zu = kt Z0

    Keys: body_acc (s^2 Zs), susp_travel, tire_defl, force (U = -C Y), body_acc_per_road_velocity
    (s^2 Zs / (s Z0)), all complex arrays shaped like omega (rad/s, > 0).
    """
    s = 1j * np.asarray(omega, dtype=np.float64)
    ms, mu, ks, cs, kt = (plant[i] for i in (P_MS, P_MU, P_KS, P_CS, P_KT))
    ctrl = kp + ki / s + kd * n_filter * s / (s + n_filter)
    one = np.ones_like(s)
    zero = np.zeros_like(s)
    h_s, h_u = {
        FB_DISPLACEMENT: (one, zero),
        FB_VELOCITY: (s, zero),
        FB_ACCELERATION: (s * s, zero),
        FB_TRAVEL: (one, -one),
    }[feedback]
    susp = ks + cs * s
    a11 = ms * s * s + susp + ctrl * h_s
    a12 = -susp + ctrl * h_u
    a21 = -susp - ctrl * h_s
    a22 = mu * s * s + susp + kt - ctrl * h_u
    det = a11 * a22 - a12 * a21
    zs = -a12 * kt / det
    zu = a11 * kt / det
    force = -ctrl * (h_s * zs + h_u * zu)
    return {
        "body_acc": s * s * zs,
        "susp_travel": zs - zu,
        "tire_defl": zu - 1.0,
        "force": force,
        "body_acc_per_road_velocity": s * zs,
    }
