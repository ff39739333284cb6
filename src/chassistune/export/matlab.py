"""MATLAB export: a .mat file holding the struct `ct` (scipy.io.savemat) and a .m script that loads
it into Simulink-style workspace variables (Ts; P, I, D, N of the Discrete PID Controller block;
breakpoints and tables of the 2-D Lookup Table blocks; ct_<param> for every parameter)."""

from __future__ import annotations

import io
from typing import Any

import numpy as np
import scipy.io

from chassistune._version import __version__
from chassistune.export.c99 import c_name
from chassistune.export.source import ExportedController


def _field(name: str) -> str:
    """A MATLAB field name (letters, digits, underscores)."""
    return c_name(name).lower()


def struct(ec: ExportedController, inputs: np.ndarray, u: np.ndarray) -> dict[str, Any]:
    """The fields of `ct` (numbers as float64, texts as char arrays, nested dicts as structs)."""
    sc = ec.scenario
    ct: dict[str, Any] = {
        "controller": ec.controller,
        "form": ec.law.form,
        "source": ec.source,
        "plant": sc.plant,
        "preset": sc.preset,
        "road": sc.road,
        "generator": f"chassistune {__version__}",
        "Ts": ec.ts_s,
        "inputs": np.array(ec.law.inputs, dtype=object),
        "params": ec.param_dict(),
        "gains": dict(ec.gains),
        "test_inputs": inputs,
        "test_u": u.reshape(-1, 1),
    }
    pid = ec.pid_form()
    if pid is not None:
        ct["pid"] = {k: (np.inf if v is None else v) for k, v in pid.items()}
    if ec.table_outputs:
        rows, cols = ec.table_inputs
        table: dict[str, Any] = {
            "rulebase": ec.rulebase,
            "orientation": f"table(i, j) is the output at {rows} = bp_{_field(rows)}(i) and "
            f"{cols} = bp_{_field(cols)}(j); read at (ke*e, kec*de/dt), clipped, "
            "bilinear (2-D Lookup Table: Interpolation-Clip)",
            f"bp_{_field(rows)}": ec.breakpoints[0],
            f"bp_{_field(cols)}": ec.breakpoints[1],
        }
        for k, out in enumerate(ec.table_outputs):
            table[_field(out)] = ec.table[k]
        ct["table"] = table
    return ct


def mat_bytes(ec: ExportedController, inputs: np.ndarray, u: np.ndarray) -> bytes:
    """The .mat file (MATLAB 5 format, readable by MATLAB, Octave and scipy.io.loadmat)."""
    buf = io.BytesIO()
    scipy.io.savemat(
        buf,
        {"ct": struct(ec, inputs, u)},
        long_field_names=True,
        do_compression=False,
        oned_as="column",
    )
    return buf.getvalue()


def script(ec: ExportedController) -> str:
    """The .m script that loads `<model>.mat` next to it into workspace variables."""
    name = ec.model_name
    lines = [
        f"% {name}.m: load {name}.mat (chassistune {__version__}) into Simulink-style variables.",
        f"% {ec.controller}: {ec.law.form}; sample time Ts.",
        f"S = load(fullfile(fileparts(mfilename('fullpath')), '{name}.mat'));",
        "ct = S.ct;",
        "Ts = ct.Ts;",
    ]
    if ec.pid_form() is not None:
        lines += [
            "% Discrete PID Controller block: P, I, D, N (form and methods in ct.pid)",
            "P = ct.pid.P;",
            "I = ct.pid.I;",
            "D = ct.pid.D;",
            "N = ct.pid.N;",
        ]
    lines += [f"ct_{_field(n)} = ct.params.{_field(n)};" for n in ec.law.params]
    if ec.table_outputs:
        lines.append("% 2-D Lookup Table blocks: row breakpoints, column breakpoints, table")
        for n in ec.table_inputs:
            lines.append(f"ct_bp_{_field(n)} = ct.table.bp_{_field(n)};")
        for n in ec.table_outputs:
            lines.append(f"ct_table_{_field(n)} = ct.table.{_field(n)};")
    return "\n".join(lines) + "\n"
