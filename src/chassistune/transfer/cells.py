"""What the transfer study runs (docs/transfer.md, "Cells"): the papers' tuned controllers
(`SOURCES`, each a cell of a shipped reproduction study and the optimizer whose run the paper's
tables show), the plants they are carried to (their paper preset, then each real car) and a car's
variants (tire, lagged slip, ECU). Whether a kernel runs a cell is asked of the plant's scenario
builder (`missing`), never declared here."""

from __future__ import annotations

import functools
import warnings
from dataclasses import dataclass
from importlib import resources

from chassistune.errors import InputError
from chassistune.plants.abs_wheel import BRAKE_FIELDS, PRESETS
from chassistune.plants.cars import CARS, shared_tir_path
from chassistune.scenarios.registry import get_plant
from chassistune.studies.spec import ScenarioConfig

RELAXATION_LENGTH_M = 0.3
"""sigma of the lagged-slip variant: CommonRoad's PAC2002 file gives no relaxation length (it has
neither LONGITUDINAL_STIFFNESS nor PTX1-3, docs/tires.md), so this is our choice, not car data."""

VEHICLE_TIR = "chrono_185_80R14_pac2002.tir"
"""The vehicle's Magic Formula tire: CommonRoad's PAC2002 set has no PKY2, which lateral forces
need (docs/tires.md), so the vehicle cells take the shipped Project Chrono 185/80 R14 file."""

VEHICLE_MF_STEP_S = 5e-4
"""The vehicle's step with the Magic Formula tire: the least whole divisor of the cars' 1 ms that
RK4's stability check passes with the Chrono tire at v_stop 2 m/s (docs/transfer.md)."""

ECUS = ("ideal", "realistic")
"""The controller's ECU: the ideal one (exact slip, continuous valve) or the realistic one
(docs/ecu.md)."""


@dataclass(frozen=True)
class Source:
    """A paper's tuned controller: cell `cell` of the reproduction's study `study`, the run of
    optimizer `optimizer` (its label) that the paper's tables show (the median by final cost)."""

    study: str
    cell: str
    optimizer: str

    @property
    def key(self) -> str:
        return f"{self.study}:{self.cell}"

    @functools.cached_property
    def scenario(self) -> ScenarioConfig:
        """The cell's scenario in the shipped study config."""
        from chassistune.papers.reproduce import shipped_config

        return next(s for s in shipped_config(self.study).scenarios if s.name == self.cell)

    @property
    def plant(self) -> str:
        return str(self.scenario.plant)

    @property
    def preset(self) -> str:
        return str(self.scenario.preset)

    @property
    def controller(self) -> str:
        return str(self.scenario.controller)

    @property
    def road_sets(self) -> tuple[tuple[str, ...], ...]:
        """What each of its tunings was tuned on: one road each (`roads`: a gain set per road,
        as the single-wheel papers' tables) or the roads together (`tune_roads`)."""
        sc = self.scenario
        if sc.tune_roads:
            return (tuple(sc.tune_roads),)
        return tuple((road,) for road in sc.roads or ())

    @property
    def roads(self) -> tuple[str, ...]:
        """Every road it was tuned on."""
        return tuple(road for roads in self.road_sets for road in roads)

    def run_scenario(self, group: str, roads: tuple[str, ...]) -> str:
        """The study's scenario name of a tuning on `roads` in the scenario group `group`
        (`studies.spec`: group/road, or group/road+road for roads tuned together)."""
        return f"{group}/{'+'.join(roads)}"


SOURCES = (
    Source("derlsp-ao-abs", "pid-100kg", "DERLSP-AO-PID"),
    Source("fuzzy-immune-abs", "pid", "DERLSP-AO"),
    Source("fuzzy-immune-abs", "fuzzy-pid", "DERLSP-AO"),
    Source("fuzzy-immune-abs", "fuzzy-immune-pid", "DERLSP-AO"),
    Source("deffao-vehicle-abs", "vehicle-fuzzy-pid", "DEFFAO-fuzzy PID"),
)
"""The papers' controllers with a stored tuning. derlsp-ao-abs's PID at the preset's 100 kg (the
paper's other reading, 200 kg, is the same plant heavier); the proposed optimizer's run each."""

TIRES = ("road", "mf", "mf+lag")
"""A car's tire: the road's curve (the paper's tire law), CommonRoad's PAC2002 Magic Formula (the
vehicle: `VEHICLE_TIR`) scaled to the road, the same with the lagged slip
(`RELAXATION_LENGTH_M`)."""


@dataclass(frozen=True)
class Cell:
    """Where a source runs: its plant's preset `target` (the paper's own, or a car), a tire
    (`TIRES`) and an ECU (`ECUS`)."""

    source: Source
    target: str
    tire: str
    ecu: str

    @property
    def name(self) -> str:
        """The cell's scenario name in the re-tuning study."""
        return f"{self.source.cell}:{self.target}:{self.tire}:{self.ecu}"

    @property
    def is_home(self) -> bool:
        """The plant the source was tuned on: the paper's preset, its road tire, the ideal ECU."""
        return self.target == self.source.preset and self.tire == "road" and self.ecu == "ideal"

    def params(self) -> dict[str, object]:
        """The runs' parameters: the source's, on a car wheel the paper preset's brake and
        actuator (docs/cars.md, "One wheel of the car"), the tire's and the ECU's."""
        out: dict[str, object] = dict(self.source.scenario.params)
        if self.source.plant == "abs-wheel" and self.target in CARS:
            paper = PRESETS[self.source.preset].params
            out |= {f: float(getattr(paper, f)) for f in BRAKE_FIELDS}
        if self.tire != "road" and self.source.plant == "abs-vehicle":
            out["tire"] = str(resources.files("chassistune") / "data" / "tires" / VEHICLE_TIR)
            out["dt_s"] = VEHICLE_MF_STEP_S
        elif self.tire != "road":
            out["tire"] = shared_tir_path()
        if self.tire == "mf+lag":
            out["relaxation_length_m"] = RELAXATION_LENGTH_M
        if self.ecu == "realistic":
            out["ecu"] = "realistic"
        return out


def cells(source: Source, cars: tuple[str, ...] = CARS) -> list[Cell]:
    """The source's cells: its paper preset with the road tire in either ECU, then every car
    with every tire in either ECU."""
    home = [Cell(source, source.preset, "road", ecu) for ecu in ECUS]
    return home + [Cell(source, car, t, ecu) for car in cars for t in TIRES for ecu in ECUS]


@functools.cache
def missing(cell: Cell) -> str | None:
    """None where the plant runs the cell on each of its roads; else what it lacks: the
    scenario builder's refusal, field and problem (without its list of known names)."""
    for road in cell.source.roads:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                get_plant(cell.source.plant).scenario(
                    cell.target, road, cell.source.controller, cell.params()
                )
        except InputError as exc:
            return f"{exc.field}: {exc.problem.split(' (known:')[0]}"
    return None
