"""Shared by the export tests: exported controllers with their vectors, and C builds via ctypes."""

from __future__ import annotations

import ctypes
import shutil
import subprocess
from dataclasses import dataclass
from functools import cache
from pathlib import Path

import numpy as np
import pytest

from chassistune.controllers import laws
from chassistune.export import c99, source, vectors
from chassistune.export.source import ExportedController
from chassistune.scenarios.abs_wheel import AbsWheelScenario
from chassistune.scenarios.registry import get_plant

LAWS = tuple(n for n in laws.names() if laws.get(n).c is not None)
"""Every law with a C form (`controllers.laws`)."""
CONTINUOUS = tuple(n for n in LAWS if not c99.c_form(n).switching)
"""The exportable laws without a discrete decision (an FMA build stays close)."""
CC = shutil.which("cc")
needs_cc = pytest.mark.skipif(CC is None, reason="no C compiler (cc) on this machine")


@dataclass(frozen=True, eq=False)
class Case:
    ec: ExportedController
    inputs: np.ndarray
    u: np.ndarray


@cache
def case(controller: str) -> Case:
    """The registry-default export of `controller` with its recorded test vectors."""
    ec = source.resolve(None, None, controller, {}, {})
    inputs, u = vectors.record(ec)
    return Case(ec, inputs, u)


def gain_rows(ec: ExportedController) -> np.ndarray:
    """The export's gains as a population of one (a row with no column for the threshold)."""
    return np.array([list(ec.gains.values())]).reshape(1, len(ec.gains))


def ideal_mode(ec: ExportedController, params: dict[str, object]) -> AbsWheelScenario:
    """The export's plant, road and controller in the IDEAL kernel (`ecu = ideal`): the
    continuous PID, the adaptive fuzzy surfaces, the laws sampled at the scenario's ts_s."""
    sc = get_plant("abs-wheel").scenario(
        ec.scenario.preset, ec.scenario.road, ec.controller, params
    )
    assert isinstance(sc, AbsWheelScenario) and sc.ecu is None
    return sc


class CLaw:
    """The exported C compiled into a shared library, called through ctypes."""

    def __init__(self, folder: Path, flags: tuple[str, ...]) -> None:
        lib = folder / "libcontroller.so"
        subprocess.run(
            [
                str(CC),
                *flags,
                "-Wall",
                "-Wextra",
                "-pedantic",
                "-Werror",
                "-shared",
                "-fPIC",
                "-o",
                str(lib),
                str(folder / c99.SOURCE),
            ],
            check=True,
        )
        self._lib = ctypes.CDLL(str(lib))
        self._lib.ct_step.restype = ctypes.c_double
        self._state = ctypes.create_string_buffer(4096)  # ct_state is a few hundred bytes

    def reset(self) -> None:
        self._lib.ct_init(self._state)

    def __call__(self, inputs: np.ndarray) -> float:
        row = np.ascontiguousarray(inputs, dtype=np.float64)
        return float(
            self._lib.ct_step(self._state, row.ctypes.data_as(ctypes.POINTER(ctypes.c_double)))
        )

    def run(self, inputs: np.ndarray) -> np.ndarray:
        self.reset()
        return np.array([self(row) for row in inputs])


def write_c(ec: ExportedController, folder: Path) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    (folder / c99.HEADER).write_text(c99.header(ec))
    (folder / c99.SOURCE).write_text(c99.source(ec))
    return folder
