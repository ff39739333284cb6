"""Test vectors of an exported controller: the ECU inputs of a closed-loop stop of its scenario
(`closed_loop.run` with the numba discrete law in the loop) and the command at each sample."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from chassistune.controllers import discrete, laws
from chassistune.export import closed_loop
from chassistune.export.source import ExportedController


class LawController:
    """The numba discrete law of an exported controller as a sampled controller (from rest)."""

    def __init__(self, ec: ExportedController) -> None:
        self._ec = ec
        self._kind = laws.kind(ec.law.controller)
        self.state = np.zeros(discrete.N_STATE)

    def __call__(self, inputs: NDArray[np.float64]) -> float:
        ec = self._ec
        return float(
            discrete.discrete_step(self._kind, self.state, inputs, ec.params, ec.table, ec.grid)
        )


def stop(ec: ExportedController) -> closed_loop.LoopResult:
    """A whole stop of the controller's scenario with its numba law sampled every ts."""
    return closed_loop.run(ec.scenario, ec.ts_s, LawController(ec), ec.law.inputs)


def record(ec: ExportedController) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """(inputs (m, n_inputs), u (m,)): one row per control step of a closed-loop stop."""
    result = stop(ec)
    return result.inputs(ec.law.inputs), result.u


def replay(ec: ExportedController, inputs: NDArray[np.float64]) -> NDArray[np.float64]:
    """The numba law's commands for recorded input rows, started from rest."""
    return discrete.run_vectors(
        laws.kind(ec.law.controller),
        np.ascontiguousarray(inputs, dtype=np.float64),
        ec.params,
        ec.table,
        ec.grid,
    )


def csv_text(names: tuple[str, ...], inputs: NDArray[np.float64], u: NDArray[np.float64]) -> str:
    """test_vectors.csv: a header of the input names and `u`, every number as Python's repr
    (the shortest decimal that reads back to the same double)."""
    lines = [",".join((*names, "u"))]
    lines += [
        ",".join(repr(float(v)) for v in (*row, value))
        for row, value in zip(inputs.tolist(), u.tolist(), strict=True)
    ]
    return "\n".join(lines) + "\n"


def read_csv(path: str) -> tuple[tuple[str, ...], NDArray[np.float64]]:
    """(header, numbers (m, n_inputs + 1)) of a test_vectors.csv."""
    with open(path, encoding="ascii") as fh:
        header = tuple(fh.readline().strip().split(","))
        rows = [[float(v) for v in line.split(",")] for line in fh if line.strip()]
    return header, np.array(rows, dtype=np.float64).reshape(len(rows), len(header))
