"""Scenarios of the quarter-car active suspension `quarter-car` (design.md 3.4).

Evaluates populations of controller gains with the exact Lyapunov objective
(`chassistune.sim.lyapunov`) or the compiled simulation (`chassistune.sim.quarter_car_kernel`) on an
ISO 8608 road (`chassistune.plants.iso_roads`). The physics is `chassistune.plants.quarter_car`.
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from chassistune.controllers import catalogue
from chassistune.controllers.specs import ControllerSpec
from chassistune.errors import InputError
from chassistune.params import as_dict, implausible, override, positive, validate
from chassistune.plants import iso_roads
from chassistune.plants import quarter_car as model
from chassistune.plants.presets import Preset
from chassistune.plants.quarter_car_params import QuarterCarParams
from chassistune.plants.roads import roughness_class
from chassistune.scenarios.base import PENALTY, Plant, Scenario, Trace, json_scalar, pick_preset
from chassistune.scenarios.registry import QUARTER_CAR
from chassistune.sim import lyapunov
from chassistune.sim import quarter_car_kernel as kernel
from chassistune.sim.batch import run_chunked

MAX_STEPS = 20_000_000
"""duration_s / dt_s above this is refused (the noise array alone would pass 160 MB)."""
MAX_TRACE_SAMPLES = 1_000_001
"""Longer traces are recorded every stride-th step."""


@dataclass(frozen=True)
class SolverParams:
    """Simulated time and step of the exact discretization (noise held over the step)."""

    duration_s: float = field(default=10.0, metadata=positive(1.0, 600.0))
    dt_s: float = field(default=1e-3, metadata=positive(1e-5, 0.01))

    @property
    def n_steps(self) -> int:
        return round(self.duration_s / self.dt_s)


@dataclass(frozen=True)
class ControllerParams:
    """Fixed parameters of the linear controllers (only `pid` exposes them)."""

    feedback: str = "body_velocity"
    n_filter: float = field(default=100.0, metadata=positive(1.0, 1e4))


OBJECTIVES = ("rms-ratio-exact", "rms-ratio")


@dataclass
class QuarterCarTrace(Trace):
    """A Trace that remembers the gains it was run with (for the frequency-response panel)."""

    gains: np.ndarray = field(default_factory=lambda: np.zeros(0))


class QuarterCarScenario(Scenario):
    """A resolved quarter-car scenario: evaluates populations of gain rows in compiled kernels."""

    objectives = OBJECTIVES
    default_objective = "rms-ratio-exact"

    def __init__(
        self,
        preset: str,
        road: str,
        controller: ControllerSpec,
        vehicle: QuarterCarParams,
        road_params: iso_roads.RoadParams,
        solver: SolverParams,
        controller_params: ControllerParams,
        seed: int,
    ) -> None:
        super().__init__("quarter-car", preset, road, controller, seed)
        self.vehicle = vehicle
        self.road_params = road_params
        self.solver = solver
        self.controller_params = controller_params
        self.plant_vector = kernel.PLANT.pack(
            {
                **as_dict(vehicle),
                "road_pole_rad_s": road_params.pole_rad_s,
                "road_gain": road_params.gain,
            }
        )
        self.feedback_code = model.FEEDBACK_CODES[controller_params.feedback]

    # -- parameters -------------------------------------------------------------------------

    def params(self) -> dict[str, Any]:
        out: dict[str, Any] = as_dict(self.vehicle)
        out.update(as_dict(self.road_params))
        out.update(as_dict(self.solver))
        if self.controller.params:
            out.update(as_dict(self.controller_params))
        out["noise_intensity"] = iso_roads.NOISE_INTENSITY
        out["damping_ratio"] = self.vehicle.damping_ratio
        out["seed"] = self.seed
        return out

    def pid_gains(self, gains: np.ndarray) -> np.ndarray:
        """The (n, 3) rows (kp, ki, kd) of the common linear controller for this controller."""
        g = np.asarray(gains, dtype=np.float64)
        k = len(self.gain_names)
        if g.ndim == 1 and g.size == k:
            g = g.reshape(1, k)
        if g.ndim != 2 or g.shape[1] != k:
            raise InputError(
                "gains",
                f"expected shape (n, {k}) for {self.controller.name}, got {tuple(np.shape(gains))}",
            )
        full = np.zeros((g.shape[0], 3))
        if self.controller.name == "pid":
            full[:] = g
        elif self.controller.name == "skyhook":
            full[:, 0] = g[:, 0]
        return full

    @property
    def _feedback(self) -> int:
        return self.feedback_code if self.controller.name == "pid" else model.FB_VELOCITY

    # -- exact (Lyapunov) -------------------------------------------------------------------

    def exact(self, gains: np.ndarray) -> np.ndarray:
        """(n, lyapunov.N_EXACT): stationary RMS (acc, travel, tire, force) and stable flag."""
        return lyapunov.exact_rms(
            self.plant_vector,
            self._feedback,
            self.controller_params.n_filter,
            self.pid_gains(gains),
        )

    @cached_property
    def passive_exact(self) -> np.ndarray:
        """Stationary RMS of the passive suspension (acc, travel, tire)."""
        return lyapunov.exact_rms(self.plant_vector, model.FB_VELOCITY, 1.0, np.zeros((1, 3)))[
            0, :3
        ]

    # -- simulation ---------------------------------------------------------------------------

    @cached_property
    def noise(self) -> np.ndarray:
        """The run's white-noise sequence (common to all candidates)."""
        return iso_roads.white_noise(self.seed, self.solver.n_steps, self.solver.dt_s)

    def simulate(self, gains: np.ndarray, workers: int | None = None) -> np.ndarray:
        """(n, kernel.N_RESULT): simulated RMS (acc, travel, tire, force) and diverged flag."""
        p, fb, nf = self.plant_vector, self._feedback, self.controller_params.n_filter
        noise, dt = self.noise, self.solver.dt_s
        no_trace = np.zeros((len(kernel.OUTPUTS), 0))

        def call(g: np.ndarray, out: np.ndarray) -> None:
            kernel.simulate_batch(p, fb, nf, g, noise, dt, no_trace, 1, out)

        return run_chunked(call, self.pid_gains(gains), kernel.N_RESULT, workers)

    @cached_property
    def passive_sim(self) -> np.ndarray:
        """Simulated RMS of the passive suspension on this run's road (acc, travel, tire)."""
        out = np.empty((1, kernel.N_RESULT))
        no_trace = np.zeros((len(kernel.OUTPUTS), 0))
        kernel.simulate_batch(
            self.plant_vector,
            model.FB_VELOCITY,
            1.0,
            np.zeros((1, 3)),
            self.noise,
            self.solver.dt_s,
            no_trace,
            1,
            out,
        )
        return out[0, :3]

    # -- metrics and costs ----------------------------------------------------------------------

    def metrics(self, gains: np.ndarray) -> dict[str, np.ndarray]:
        exact = self.exact(gains)
        sim = self.simulate(gains)
        stable = exact[:, lyapunov.E_STABLE] == 1.0
        rms = kernel.RESULT.decode(sim)
        diverged = rms.pop("diverged") == 1.0
        n = sim.shape[0]
        ps = self.passive_sim
        v = self.vehicle
        return {
            "body_acc_rms": rms["body_acc_rms"],
            "susp_travel_rms": rms["susp_travel_rms"],
            "tire_defl_rms": rms["tire_defl_rms"],
            "objective": lyapunov.rms_ratio(sim, ps, stable & ~diverged, PENALTY),
            "objective_exact": lyapunov.rms_ratio(exact, self.passive_exact, stable, PENALTY),
            "passive_body_acc_rms": np.full(n, ps[0]),
            "passive_susp_travel_rms": np.full(n, ps[1]),
            "passive_tire_defl_rms": np.full(n, ps[2]),
            "force_rms": rms["force_rms"],
            "damping_ratio": np.full(n, v.damping_ratio),
            "travel_3sigma_m": 3.0 * rms["susp_travel_rms"],
            "dynamic_tire_load_ratio": (
                v.tire_stiffness_n_m * rms["tire_defl_rms"] / v.static_tire_load_n
            ),
            "stable": stable,
            "diverged": diverged,
        }

    def cost(
        self, gains: np.ndarray, objective: str | None = None, workers: int | None = None
    ) -> np.ndarray:
        """Eq. 10 per row; `workers` threads for the simulation (default: all cores)."""
        objective = self.pick_objective(objective)
        exact = self.exact(gains)
        stable = exact[:, lyapunov.E_STABLE] == 1.0
        if objective == "rms-ratio-exact":
            return lyapunov.rms_ratio(exact, self.passive_exact, stable, PENALTY)
        sim = self.simulate(gains, workers)
        usable = stable & (sim[:, kernel.RESULT["diverged"]] == 0.0)
        return lyapunov.rms_ratio(sim, self.passive_sim, usable, PENALTY)

    # -- traces and frequency responses ---------------------------------------------------------

    def _trace_run(self, pid: np.ndarray, feedback: int, stride: int, n_rec: int) -> np.ndarray:
        rec = np.zeros((len(kernel.OUTPUTS), n_rec))
        out = np.empty((1, kernel.N_RESULT))
        kernel.simulate_batch(
            self.plant_vector,
            feedback,
            self.controller_params.n_filter,
            pid.reshape(1, 3),
            self.noise,
            self.solver.dt_s,
            rec,
            stride,
            out,
        )
        return rec

    def trace(self, gains: np.ndarray) -> QuarterCarTrace:
        g = np.asarray(gains, dtype=np.float64).reshape(-1)
        pid = self.pid_gains(g.reshape(1, -1))[0]
        n_steps = self.solver.n_steps
        stride = max(1, math.ceil((n_steps + 1) / MAX_TRACE_SAMPLES))
        n_rec = n_steps // stride + 1
        active = self._trace_run(pid, self._feedback, stride, n_rec)
        passive = self._trace_run(np.zeros(3), model.FB_VELOCITY, stride, n_rec)
        out = kernel.OUTPUTS
        signals = {"time_s": np.arange(n_rec) * stride * self.solver.dt_s}
        units = {"time_s": "s"}
        for prefix, rows, names in (
            ("", active, TRACE_SIGNALS),
            ("passive_", passive, PASSIVE_SIGNALS),
        ):
            for name in names:
                signals[prefix + name] = rows[out[TRACE_SIGNALS[name]]]
                units[prefix + name] = out.units[TRACE_SIGNALS[name]]
        metrics = {k: json_scalar(v[0]) for k, v in self.metrics(g.reshape(1, -1)).items()}
        return QuarterCarTrace(signals, metrics, units, gains=g.copy())

    def frequency_response(self, gains: np.ndarray, freq_hz: np.ndarray) -> dict[str, np.ndarray]:
        """|body acceleration / road velocity| (1/s) of the active and passive loops at freq_hz."""
        pid = self.pid_gains(np.asarray(gains, dtype=np.float64).reshape(1, -1))[0]
        omega = 2.0 * math.pi * np.asarray(freq_hz, dtype=np.float64)
        key = "body_acc_per_road_velocity"
        active = model.frequency_response(
            self.plant_vector,
            self._feedback,
            pid[0],
            pid[1],
            pid[2],
            self.controller_params.n_filter,
            omega,
        )[key]
        passive = model.frequency_response(
            self.plant_vector, model.FB_VELOCITY, 0.0, 0.0, 0.0, 1.0, omega
        )[key]
        return {
            "freq_hz": np.asarray(freq_hz, dtype=np.float64),
            "active": np.abs(active),
            "passive": np.abs(passive),
        }


TRACE_SIGNALS = {
    "road_m": "road",
    "body_acc_m_s2": "body_acc",
    "susp_travel_m": "susp_travel",
    "tire_defl_m": "tire_defl",
    "force_n": "force",
    "body_disp_m": "body_disp",
}
"""Trace signal name -> output row of the kernel's trace (`kernel.OUTPUTS`)."""
PASSIVE_SIGNALS = ("body_acc_m_s2", "susp_travel_m", "tire_defl_m")
"""Signals also traced for the passive suspension on the same road (as passive_<name>)."""


class QuarterCarPlant(Plant[QuarterCarScenario]):
    """The quarter-car active suspension plant."""

    spec = QUARTER_CAR

    def controllers(self) -> list[ControllerSpec]:
        return catalogue.for_plant(QUARTER_CAR.name)

    def parameter_sets(self, preset: str | None = None) -> dict[str, Any]:
        presets = self.spec.preset_table()
        pre = presets[pick_preset(self.name, preset, self.default_preset, presets)]
        road = pre.info.roads[0]
        return {
            "plant": pre.params,
            f"road ({road}; others have their own gq_m3)": iso_roads.RoadParams(
                gq_m3=roughness_class(road)
            ),
            "solver": SolverParams(),
        }

    def build(
        self,
        preset: str,
        pre: Preset[QuarterCarParams],
        road: str,
        controller: str,
        values: dict[str, object],
        seed: int,
    ) -> QuarterCarScenario:
        gq = roughness_class(road)
        spec = catalogue.get(QUARTER_CAR.name, "passive" if controller == "none" else controller)
        if isinstance(seed, bool) or not isinstance(seed, int | np.integer) or seed < 0:
            raise InputError("seed", f"must be a non-negative integer, got {seed!r}")
        vehicle, used = override(pre.params, values)
        road_params, used_road = override(iso_roads.RoadParams(gq_m3=gq), values)
        solver, used_solver = override(SolverParams(), values)
        ctrl_values = {k: v for k, v in values.items() if k in spec.param_names}
        ctrl, used_ctrl = override(ControllerParams(), ctrl_values)
        used |= used_road | used_solver | used_ctrl
        unknown = sorted(set(values) - used)
        if unknown:
            known = sorted(
                {f.name for f in dataclasses.fields(QuarterCarParams)}
                | {f.name for f in dataclasses.fields(iso_roads.RoadParams)}
                | {f.name for f in dataclasses.fields(SolverParams)}
                | set(spec.param_names)
            )
            raise InputError(
                f"params.{unknown[0]}",
                f"unknown parameter for quarter-car with {spec.name} (known: {', '.join(known)})",
            )
        if ctrl.feedback not in model.FEEDBACK_CODES:
            raise InputError(
                "params.feedback",
                f"unknown feedback {ctrl.feedback!r} (known: {', '.join(model.FEEDBACK_CODES)})",
            )
        iso_roads.validate_road(road_params)
        _check_solver(solver)
        scenario = QuarterCarScenario(
            preset, road, spec, validate(vehicle, "params."), road_params, solver, ctrl, int(seed)
        )
        for obj in (vehicle, road_params, solver, ctrl):
            for warning in implausible(obj):  # valid input only
                warnings.warn(warning, stacklevel=2)
        return scenario


def _check_solver(solver: SolverParams) -> None:
    if solver.dt_s > 0.01:
        raise InputError(
            "params.dt_s",
            f"must be at most 0.01 s (the road noise is held over the step), got {solver.dt_s:g}",
        )
    if solver.duration_s < solver.dt_s:
        raise InputError(
            "params.duration_s",
            f"must be at least one step dt_s = {solver.dt_s:g}, got {solver.duration_s:g}",
        )
    if solver.n_steps > MAX_STEPS:
        raise InputError(
            "params.duration_s",
            f"too many steps: duration_s / dt_s = {solver.n_steps} exceeds {MAX_STEPS}",
        )


PLANT = QuarterCarPlant()
