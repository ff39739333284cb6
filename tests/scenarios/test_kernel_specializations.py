"""A tune runs the kernel specialization that `warmup` compiled: an optimizer's read-only
population must not make numba compile a second one (a minute of CPU at a user's first tune)."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np

from chassistune.controllers.catalogue import get as get_controller
from chassistune.scenarios.controller_params import kernel_gains

_PROBE = """
import json
from chassistune.tuning.tune import tune
from chassistune.sim import abs_vehicle_kernel as V
from chassistune.sim.abs_wheel_kernel import entry_point

tune("abs-wheel", "pid", "pso", pop_size=6, max_iter=1, seed=1)
tune("abs-vehicle", "pid", "pso", pop_size=6, max_iter=1, seed=1)
print(json.dumps({
    "wheel": [str(s[1]) for s in entry_point().signatures],
    "vehicle": [str(s[0]) for s in V.entry_point().signatures],
}))
"""


def test_read_only_gains_become_a_writeable_array() -> None:
    asked = np.array([[5000.0, 0.0, 230.0]])
    asked.flags.writeable = False
    g = kernel_gains(asked, get_controller("abs-wheel", "pid"))
    assert g.flags.writeable and g.flags.c_contiguous
    assert g.tobytes() == asked.tobytes()


def test_a_tune_uses_one_writeable_kernel_specialization() -> None:
    out = subprocess.run(
        [sys.executable, "-c", _PROBE], capture_output=True, text=True, check=True, timeout=900
    )
    sigs = json.loads(out.stdout.splitlines()[-1])
    for name in ("wheel", "vehicle"):
        assert len(sigs[name]) == 1, sigs[name]
        assert not sigs[name][0].startswith("readonly"), f"{name}: {sigs[name][0]}"
