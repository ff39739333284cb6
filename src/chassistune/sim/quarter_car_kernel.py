"""Compiled batch simulation of the quarter car on a random road (design.md 2, 3.4).

Each candidate's closed loop (the *explicit* realization of `plants.quarter_car`: integrator and
derivative-filter states as a block diagram has them) is discretized exactly,
x[k+1] = Phi x[k] + gamma w[k], with the road's white noise w[k] ~ N(0, W/dt) held over the step
(W = 1/2); the controller acts continuously inside the step, so the only approximation is the
held noise. All candidates share one noise sequence (common random numbers). The time loop is
outside and the loop over candidates inside (arrays laid out candidates-last, so the compiler
vectorizes across candidates). A candidate whose state leaves |x| < DIVERGED_ABOVE, or turns NaN,
is marked diverged and frozen at zero. A single run is a batch of one; `trace` records every
`stride`-th sample of all outputs for plots.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from chassistune.layout import Layout, Slot
from chassistune.plants.quarter_car import (
    MAX_STATES,
    N_OUT,
    OUTPUT_SLOTS,
    PLANT_SLOTS,
    closed_loop,
)
from chassistune.sim.lti import discretize_zoh

PLANT = Layout("quarter-car plant vector", tuple(Slot(*s) for s in PLANT_SLOTS))
OUTPUTS = Layout("quarter-car outputs (trace rows)", tuple(Slot(*s) for s in OUTPUT_SLOTS))
N_RMS = 4
"""Outputs 0..3 (acc, travel, tire, force) are accumulated, into result columns 0..3."""
RMS_SLOTS = tuple(
    Slot(f"{name}_rms", unit, f"RMS of the {meaning}")
    for name, unit, meaning in OUTPUT_SLOTS[:N_RMS]
)
RESULT = Layout(
    "quarter-car simulation results",
    (*RMS_SLOTS, Slot("diverged", "-", "1 if the state left |x| < DIVERGED_ABOVE or turned NaN")),
)
R_ACC, R_TRAVEL, R_TIRE, R_FORCE, R_DIVERGED = (RESULT[n] for n in RESULT.names)
N_RESULT = len(RESULT)

DIVERGED_ABOVE = 1e6
BLOCK = 64
_CHECK_EVERY = 512


@njit(cache=True, nogil=True)
def simulate_batch(
    plant: np.ndarray,
    feedback: int,
    n_filter: float,
    gains: np.ndarray,
    noise: np.ndarray,
    dt: float,
    trace: np.ndarray,
    stride: int,
    out: np.ndarray,
) -> None:
    """Simulate len(noise) steps of every row of gains (n, 3) = (kp, ki, kd); results into out.

    out (n, N_RESULT): RMS over samples 1..len(noise) of the first N_RMS outputs, and the
    diverged flag. trace (N_OUT, n_rec): if n_rec > 0, outputs of candidate 0 at samples
    0, stride, 2 stride, ... (sample k is time k dt, sample 0 the initial rest state).
    Candidates run in blocks of BLOCK so that a block's matrices stay in cache.
    """
    no_trace = np.zeros((N_OUT, 0))
    for lo in range(0, gains.shape[0], BLOCK):
        hi = min(lo + BLOCK, gains.shape[0])
        phi, gam, cm, diverged = _discretize(plant, feedback, n_filter, gains[lo:hi], dt)
        _run_block(
            phi, gam, cm, diverged, noise, trace if lo == 0 else no_trace, stride, out[lo:hi]
        )


@njit(cache=True, nogil=True)
def _discretize(
    plant: np.ndarray, feedback: int, n_filter: float, gains: np.ndarray, dt: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(Phi, gamma, C, diverged) of each candidate's closed loop, candidates last; a candidate
    without a closed loop is marked diverged (zero matrices)."""
    n = gains.shape[0]
    ms = MAX_STATES
    phi = np.zeros((ms, ms, n))
    gam = np.zeros((ms, n))
    cm = np.zeros((N_OUT, ms, n))
    a = np.zeros((ms, ms))
    b = np.zeros(ms)
    c = np.zeros((N_OUT, ms))
    phi1 = np.zeros((ms, ms))
    gam1 = np.zeros(ms)
    diverged = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        m = closed_loop(
            plant, feedback, gains[i, 0], gains[i, 1], gains[i, 2], n_filter, True, a, b, c
        )
        if m < 0:
            diverged[i] = True
            continue
        discretize_zoh(a, b, m, dt, phi1, gam1)
        phi[:m, :m, i] = phi1[:m, :m]
        gam[:m, i] = gam1[:m]
        cm[:, :m, i] = c[:, :m]
    return phi, gam, cm, diverged


@njit(cache=True, nogil=True)
def _run_block(
    phi: np.ndarray,
    gam: np.ndarray,
    cm: np.ndarray,
    diverged: np.ndarray,
    noise: np.ndarray,
    trace: np.ndarray,
    stride: int,
    out: np.ndarray,
) -> None:
    """The time loop of a block of candidates (`simulate_batch`'s noise, trace and results)."""
    n = diverged.shape[0]
    ms = MAX_STATES
    x = np.zeros((ms, n))
    xn = np.zeros((ms, n))
    y = np.zeros(n)
    sumsq = np.zeros((N_RMS, n))
    n_steps = noise.shape[0]
    n_rec = trace.shape[1]
    if n_rec > 0:
        trace[:, 0] = 0.0
    for k in range(n_steps):
        wk = noise[k]
        for r in range(ms):
            for i in range(n):
                xn[r, i] = gam[r, i] * wk
            for q in range(ms):
                for i in range(n):
                    xn[r, i] += phi[r, q, i] * x[q, i]
        x, xn = xn, x
        for o in range(N_RMS):
            for i in range(n):
                y[i] = 0.0
            for q in range(ms):
                for i in range(n):
                    y[i] += cm[o, q, i] * x[q, i]
            for i in range(n):
                sumsq[o, i] += y[i] * y[i]
        if n_rec > 0 and (k + 1) % stride == 0 and (k + 1) // stride < n_rec:
            j = (k + 1) // stride
            for o in range(N_OUT):
                acc = 0.0
                for q in range(ms):
                    acc += cm[o, q, 0] * x[q, 0]
                trace[o, j] = acc
        if (k + 1) % _CHECK_EVERY == 0 or k + 1 == n_steps:
            for i in range(n):
                for q in range(ms):
                    if not abs(x[q, i]) < DIVERGED_ABOVE:
                        diverged[i] = True
                if diverged[i]:
                    x[:, i] = 0.0
                    phi[:, :, i] = 0.0
                    gam[:, i] = 0.0
    for i in range(n):
        for o in range(N_RMS):
            out[i, o] = np.nan if diverged[i] else np.sqrt(sumsq[o, i] / n_steps)
        out[i, R_DIVERGED] = 1.0 if diverged[i] else 0.0
