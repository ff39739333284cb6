"""Measured cars for the 7-DOF vehicle ABS plant: CommonRoad's parameter sets of a Ford Escort,
a BMW 320i and a VW Vanagon (commonroad-vehicle-models 3.0.2, BSD-3-Clause), carried over number
for number in `data/cars/*.toml`, and their mapping onto `VehicleParams` (docs/cars.md).

Light at import (tomllib only): the presets are listed without numba.
"""

from __future__ import annotations

import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from importlib import resources
from typing import Any

CARS = ("ford-escort", "bmw-320i", "vw-vanagon")
"""The preset names, one TOML file each under data/cars."""
SHARED = "commonroad-shared"
"""The wheel and tire data the three cars share (data/cars/commonroad-shared.toml)."""

FROM_CAR = {
    "mass_kg": "m",
    "front_unsprung_kg": "m_uf",
    "rear_unsprung_kg": "m_ur",
    "yaw_inertia_kg_m2": "I_z",
    "wheel_inertia_kg_m2": "I_y_w",
    "wheel_radius_m": "R_w",
    "cg_to_front_m": "a",
    "cg_to_rear_m": "b",
    "cg_height_m": "h_cg",
    "track_front_m": "T_f",
    "track_rear_m": "T_r",
    "front_brake_share": "T_sb",
}
"""VehicleParams field -> the CommonRoad field it takes verbatim."""


@dataclass(frozen=True)
class Car:
    """One car's data: CommonRoad's fields (its own and the shared wheel ones), the shared
    tire's p_ky1, the step its preset runs at, and the source."""

    name: str
    title: str
    vehicle: Mapping[str, Any]
    p_ky1: float
    dt_s: float
    source: Mapping[str, Any]

    def cornering_stiffness_n_rad(self, g_m_s2: float) -> float:
        """|p_ky1| F_z at the mean static load m g / 4: CommonRoad's K_y = p_ky1 F_z."""
        return abs(self.p_ky1) * float(self.vehicle["m"]) * g_m_s2 / 4.0

    def values(self, g_m_s2: float) -> dict[str, float]:
        """The VehicleParams fields this car sets (every other field keeps its default)."""
        out = {name: float(self.vehicle[key]) for name, key in FROM_CAR.items()}
        out["cornering_stiffness_n_rad"] = self.cornering_stiffness_n_rad(g_m_s2)
        out["dt_s"] = self.dt_s
        return out

    def front_wheel_values(self) -> dict[str, float]:
        """One front wheel as the single wheel (docs/cars.md, "One wheel of the car"): the mass
        whose weight is the front wheel's static load, m b / (2 (a + b)) (the front axle carries
        m g b / L at rest, split evenly), and the shared wheel radius and inertia."""
        v = self.vehicle
        a, b = float(v["a"]), float(v["b"])
        return {
            "mass_kg": float(v["m"]) * b / (2.0 * (a + b)),
            "wheel_radius_m": float(v["R_w"]),
            "wheel_inertia_kg_m2": float(v["I_y_w"]),
        }

    def description(self, g_m_s2: float) -> str:
        """One line for `list presets`: the car, its source and its key numbers."""
        v = self.values(g_m_s2)
        return (
            f"{self.title}, CommonRoad vehicle {self.source['vehicle_id']} "
            f"({self.source['package']} {self.source['version']}, BSD-3-Clause): "
            f"m = {v['mass_kg']:.1f} kg, Iz = {v['yaw_inertia_kg_m2']:.1f} kg m^2, "
            f"lf/lr = {v['cg_to_front_m']:.3f}/{v['cg_to_rear_m']:.3f} m, "
            f"h = {v['cg_height_m']:.3f} m, tracks {v['track_front_m']:.3f}/"
            f"{v['track_rear_m']:.3f} m, R = {v['wheel_radius_m']} m, "
            f"J = {v['wheel_inertia_kg_m2']} kg m^2, "
            f"C = |PKY1| m g/4 = {v['cornering_stiffness_n_rad'] / 1e3:.1f} kN/rad; "
            f"front brake share T_sb = {v['front_brake_share']}; "
            f"paper-deffao's brake gain and actuator, v0 and g; dt = {self.dt_s * 1e3:g} ms"
        )


def _read(name: str) -> dict[str, Any]:
    text = resources.files("chassistune").joinpath(f"data/cars/{name}.toml").read_text("utf-8")
    return tomllib.loads(text)


def read_car(name: str) -> Car:
    """The car `name` of CARS, its own fields merged with the shared wheel data."""
    data, shared = _read(name), _read(SHARED)
    return Car(
        name,
        data["source"]["title"],
        {**data["vehicle"], **shared["vehicle"]},
        float(shared["tire"]["p_ky1"]),
        float(data["preset"]["dt_s"]),
        data["source"],
    )


def shared_tir_path() -> str:
    """The path of the TIR file the three cars share (data/cars/commonroad-shared.toml's
    `tire.tir_file`: CommonRoad's PAC2002 set, docs/tires.md)."""
    return str(resources.files("chassistune").joinpath("data", _read(SHARED)["tire"]["tir_file"]))
