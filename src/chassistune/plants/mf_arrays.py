"""The Magic Formula forces over numpy arrays: the compiled scalar functions of
`plants.magic_formula` (Pacejka 2012, eqs. 4.E50 and 4.E58, combined slip) looped over
broadcast inputs, for curves, tables and reference checks outside the kernels."""

from __future__ import annotations

import numba
import numpy as np
from numpy.typing import ArrayLike

from chassistune.plants.magic_formula import lateral_force_n, longitudinal_force_n
from chassistune.plants.mf_coefficients import MagicFormulaTire


@numba.njit(cache=True, nogil=True, error_model="numpy")
def _fill_forces(
    c: np.ndarray,
    kappa: np.ndarray,
    alpha: np.ndarray,
    fz_n: np.ndarray,
    fx_n: np.ndarray,
    fy_n: np.ndarray,
) -> None:
    for i in range(kappa.size):
        fx_n[i] = longitudinal_force_n(c, kappa[i], alpha[i], fz_n[i])
        fy_n[i] = lateral_force_n(c, kappa[i], alpha[i], fz_n[i])


def forces_n(
    tire: MagicFormulaTire, kappa: ArrayLike, alpha: ArrayLike, fz_n: ArrayLike
) -> tuple[np.ndarray, np.ndarray]:
    """(F_x, F_y) in N, of the broadcast shape of the longitudinal slip kappa, the lateral slip
    alpha* = tan(alpha) and the load fz_n; bit for bit the scalar functions' values."""
    k, a, fz = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (kappa, alpha, fz_n)))
    fx = np.empty(k.shape)
    fy = np.empty(k.shape)
    _fill_forces(
        tire.kernel_array(), k.ravel(), a.ravel(), fz.ravel(), fx.reshape(-1), fy.reshape(-1)
    )
    return fx, fy
