"""What the ABS scenarios share about a controller: its fixed parameters resolved from `--param`
values, and a population of gain rows checked and shaped for a kernel."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from chassistune.controllers.specs import ControllerSpec
from chassistune.errors import InputError
from chassistune.params import to_float


def resolve_controller_params(
    spec: ControllerSpec,
    values: Mapping[str, object],
    used: set[str],
    defaults: Mapping[str, float],
    amplitude: float,
) -> dict[str, Any]:
    """The controller's fixed parameters: given values (strings checked against their choices,
    numbers finite and, where required, positive), else the preset's defaults, else the
    catalogue's; `amplitude` (the driver's command) when the law has one and none was given.
    Adds the names it used to `used`."""
    out: dict[str, Any] = {}
    for ps in spec.params:
        if isinstance(ps.default, str):
            value = str(values.get(ps.name, ps.default))
            if ps.choices and value not in ps.choices:
                raise InputError(
                    f"params.{ps.name}", f"must be one of {', '.join(ps.choices)}, got {value!r}"
                )
            out[ps.name] = value
            used.add(ps.name)
            continue
        if ps.name in values:
            out[ps.name] = to_float(values[ps.name], f"params.{ps.name}")
            used.add(ps.name)
        elif ps.name in defaults:
            out[ps.name] = defaults[ps.name]
        elif isinstance(ps.default, float):
            out[ps.name] = ps.default
        if ps.positive and ps.name in out and not out[ps.name] > 0:
            raise InputError(f"params.{ps.name}", f"must be positive, got {out[ps.name]:g}")
        if ps.integers is not None and ps.name in out:
            lo, hi = ps.integers
            if out[ps.name] not in range(lo, hi + 1):
                raise InputError(
                    f"params.{ps.name}", f"must be an integer {lo} .. {hi}, got {out[ps.name]:g}"
                )
    if "amplitude" in spec.param_names and "amplitude" not in out:
        out["amplitude"] = amplitude
    return out


def kernel_gains(gains: np.ndarray, spec: ControllerSpec) -> np.ndarray:
    """Gain rows (n, k) as a C-contiguous, writeable float array; one dummy column for laws
    without gains (the kernels read none). Writeable because numba compiles a separate
    specialization of a kernel for a read-only array (an optimizer's `ask()` returns one): a
    second compile of a minute of CPU at a user's first tune, after `warmup` compiled the first."""
    g = np.asarray(gains, dtype=np.float64)
    if g.ndim == 1:
        g = g[None, :]
    k = len(spec.gain_names)
    if g.ndim != 2 or g.shape[1] != k:
        raise InputError(
            "gains", f"expected shape (n, {k}) for {spec.name}, got {tuple(np.shape(gains))}"
        )
    if k == 0:
        return np.zeros((g.shape[0], 1))
    return np.require(g, requirements=("C", "W"))
