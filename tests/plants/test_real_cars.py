"""The measured-car presets of the 7-DOF vehicle (docs/cars.md): CommonRoad's numbers carried over
exactly, physics on the dry road, straight-line symmetry, the integration step as measured, the
conformance check, and the CLI."""

from __future__ import annotations

import dataclasses
import json
import re
from importlib.metadata import version
from importlib.resources import files
from pathlib import Path

import numpy as np
import pytest
from mf_tires import sample_tire

from chassistune.plants.abs_vehicle_params import PRESETS, VehicleParams
from chassistune.plants.cars import CARS, FROM_CAR, read_car
from chassistune.scenarios.abs_vehicle import PLANT
from chassistune.scenarios.check import check_plant

VEHICLE_IDS = {"ford-escort": 1, "bmw-320i": 2, "vw-vanagon": 3}
STEPS_S = {"ford-escort": 1e-3, "bmw-320i": 1e-3, "vw-vanagon": 2.5e-4}
"""The step each preset runs at, as measured (docs/cars.md, integration step)."""
CONTROLLERS = ["none", "pid", "fuzzy-pid", "threshold"]
ROADS = [("dry-concrete", {}), ("ice", {}), ("mu-jump", {}), ("split-mu", {"steering": "fixed"}),
         ("split-mu", {"steering": "driver"})]  # fmt: skip
DT_REL_TOL = 1e-3
"""Stop-distance tolerance of a preset's step against dt/4 (docs/cars.md, integration step)."""
DOCS = Path(__file__).resolve().parents[2] / "docs"


def commonroad(name: str) -> dict:
    """CommonRoad's own parameter set of the car (skips without the package)."""
    vp = pytest.importorskip("vehiclemodels.vehicle_parameters")
    return dataclasses.asdict(vp.setup_vehicle_parameters(VEHICLE_IDS[name]))


def stop_distance_m(car: str, road: str, controller: str, **params: object) -> float:
    sc = PLANT.scenario(car, road, controller, params)
    return float(sc.metrics(sc.gains_array(None))["stop_distance_m"][0])


def test_the_cars_are_the_three_commonroad_sets_and_presets() -> None:
    assert set(CARS) == set(VEHICLE_IDS)
    assert set(CARS) < set(PRESETS) and PLANT.presets().keys() == PRESETS.keys()


@pytest.mark.parametrize("car", CARS)
def test_every_carried_number_equals_commonroads(car: str) -> None:
    theirs = commonroad(car)
    data = read_car(car)
    carried = set(theirs) - {"tire", "trailer"}  # the tire: the TIR file; trailer: all None
    assert set(data.vehicle) == carried
    for key in carried:
        assert data.vehicle[key] == theirs[key], key
    assert all(v is None for v in theirs["trailer"].values())
    assert data.p_ky1 == theirs["tire"]["p_ky1"]
    assert data.source["version"] == version("commonroad-vehicle-models")
    assert data.source["vehicle_id"] == VEHICLE_IDS[car]


@pytest.mark.parametrize("car", CARS)
def test_the_preset_takes_the_cars_numbers_and_keeps_the_rest(car: str) -> None:
    theirs, pp, base = commonroad(car), PRESETS[car].params, VehicleParams()
    for name, key in FROM_CAR.items():
        assert getattr(pp, name) == theirs[key], name
    g = base.g_m_s2
    assert pp.cornering_stiffness_n_rad == abs(theirs["tire"]["p_ky1"]) * theirs["m"] * g / 4
    assert pp.dt_s == STEPS_S[car]
    own = {*FROM_CAR, "cornering_stiffness_n_rad", "dt_s"}
    for f in dataclasses.fields(VehicleParams):
        if f.name not in own:
            assert getattr(pp, f.name) == getattr(base, f.name), f.name


def test_the_three_cars_share_one_tire_and_wheel_set() -> None:
    sets = [commonroad(car) for car in CARS]
    shared = {k for k in sets[0] if all(s[k] == sets[0][k] for s in sets)}
    assert {"tire", "R_w", "I_y_w"} <= shared
    assert not {"m", "a", "b", "h_cg", "I_z", "T_f", "T_r", "T_sb"} & shared
    tir = sample_tire()  # the shipped TIR file of the same set
    assert tir.unloaded_radius_m == sets[0]["R_w"]
    assert tir.pdx1 == sets[0]["tire"]["p_dx1"] and tir.pkx1 == sets[0]["tire"]["p_kx1"]
    text = (files("chassistune") / "data" / "tires" / "commonroad_pac2002.tir").read_text()
    pky1 = re.search(r"^PKY1\s*=\s*(\S+)", text, re.MULTILINE)
    assert pky1 is not None and float(pky1.group(1)) == read_car(CARS[0]).p_ky1


@pytest.mark.parametrize("car", CARS)
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_dry_stop_lies_between_the_adhesion_bound_and_locked_wheels(car, controller) -> None:
    sc = PLANT.scenario(car, "dry-concrete", controller)
    m = sc.trace(sc.gains_array(None)).metrics
    pp, surface = sc.plant_params, sc.road_spec.surfaces[0]
    locked_m = (pp.v0_m_s**2 - pp.v_stop_m_s**2) / (2 * surface.mu_lock * pp.g_m_s2)
    assert m["stopped"]
    assert m["bound_distance_m"] <= m["stop_distance_m"]
    # no law does worse than locking all four wheels after the pedal's 0.15 s ramp
    assert m["stop_distance_m"] <= locked_m + 0.15 * pp.v0_m_s
    if controller in ("pid", "fuzzy-pid"):
        assert m["stop_distance_m"] <= 1.06 * m["bound_distance_m"]
        assert m["locked_time_s"] == 0.0
    if controller == "none":
        assert m["stop_distance_m"] >= locked_m


@pytest.mark.parametrize("car", CARS)
@pytest.mark.parametrize("road", ["dry-concrete", "ice", "mu-jump"])
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_straight_braking_on_a_symmetric_road_gives_no_yaw(car, road, controller) -> None:
    sc = PLANT.scenario(car, road, controller)
    s = sc.trace(sc.gains_array(None)).signals
    for name in ("yaw_rate_rad_s", "heading_rad", "y_m", "vy_m_s"):
        assert np.all(s[name] == 0.0), name


@pytest.mark.parametrize("car", CARS)
@pytest.mark.parametrize("road,extra", ROADS)
@pytest.mark.parametrize("controller", CONTROLLERS)
def test_the_presets_step_is_converged(car, road, extra, controller) -> None:
    """The stop distance at the preset's step within DT_REL_TOL of dt/4's (docs/cars.md)."""
    dt = PRESETS[car].params.dt_s
    coarse = stop_distance_m(car, road, controller, **extra)
    fine = stop_distance_m(car, road, controller, dt_s=dt / 4, **extra)
    assert abs(coarse - fine) <= DT_REL_TOL * fine


def test_twice_the_step_samples_the_laws_too_slowly() -> None:
    """Why not 2 ms (docs/cars.md): the 1 ms sample period then becomes 2 ms, and the threshold
    law on ice moves by more than the tolerance; the continuous PID does not."""
    car = "vw-vanagon"
    ref = stop_distance_m(car, "ice", "threshold", dt_s=2.5e-4)
    assert abs(stop_distance_m(car, "ice", "threshold", dt_s=2e-3) - ref) > 10 * DT_REL_TOL * ref
    pid = stop_distance_m(car, "ice", "pid", dt_s=2.5e-4)
    assert abs(stop_distance_m(car, "ice", "pid", dt_s=2e-3) - pid) < 1e-5 * pid


@pytest.mark.parametrize("car", CARS)
def test_split_mu_yaw_agrees_with_an_independent_scipy_integration(car: str) -> None:
    """Each car's geometry (lf != lr, tf != tr, its h and Iz) through the kernel's RK4 at the
    preset's step against scipy's RK45 (rtol 1e-8) on the plain-Python right-hand side of
    perf/vehicle.py, over the first 0.6 s of split-mu braking (yaw, lateral slip, Newton loads)."""
    from chassistune.perf.vehicle import reference_solution

    sc = PLANT.scenario(car, "split-mu", "pid", {"t_max_s": 0.6, "steering": "fixed"})
    g = sc.gains_array(None)
    sol = reference_solution(sc, g, rtol=1e-8, atol=1e-9)
    s = sc.trace(g).signals
    rows = {"vx_m_s": 0, "vy_m_s": 1, "yaw_rate_rad_s": 2, "y_m": 4, "heading_rad": 5}
    for name, row in {**rows, "distance_m": 26}.items():
        assert s[name][-1] == pytest.approx(sol.y[row, -1], rel=1e-5), name
    assert abs(s["yaw_rate_rad_s"][-1]) > 0.3  # a real yaw, not a trivial agreement


@pytest.mark.parametrize("car", CARS)
def test_each_car_passes_the_conformance_check(car: str) -> None:
    check_plant("abs-vehicle", preset=car)


@pytest.mark.parametrize("car", CARS)
def test_simulate_runs_each_car_from_the_cli(cli, car: str) -> None:
    r = cli("simulate", "abs-vehicle", "--preset", car, "--controller", "pid", "--json")
    assert r.code == 0 and r.err == "", r.err
    doc = json.loads(r.out)
    assert doc["preset"] == car and doc["params"]["mass_kg"] == PRESETS[car].params.mass_kg
    assert doc["metrics"]["stopped"] is True


def test_list_presets_names_the_cars(cli) -> None:
    r = cli("list", "presets", "--json")
    assert r.code == 0
    listed = json.loads(r.out)["presets"]["abs-vehicle"]
    cars = {p["name"]: p for p in listed if p["name"] in CARS}
    assert list(cars) == list(CARS)
    for car, p in cars.items():
        assert p["roads"][0] == "dry-concrete" and read_car(car).title in p["description"]


def test_tune_takes_a_car_preset(cli) -> None:
    r = cli("tune", "abs-vehicle", "--preset", "bmw-320i", "--controller", "pid",
            "--optimizer", "de", "--pop", "4", "--iters", "1", "--json")  # fmt: skip
    assert r.code == 0, r.err
    assert json.loads(r.out)["preset"] == "bmw-320i"


def test_docs_say_where_every_field_comes_from() -> None:
    text = (DOCS / "cars.md").read_text()
    for f in dataclasses.fields(VehicleParams):
        assert f"`{f.name}`" in text, f.name
    assert "cars.md" in (DOCS / "vehicle.md").read_text()
