"""What the league runs: per ABS plant its preset and mode, the training roads every law is
tuned on together (robust over roads: the mean cost), and the held-out cases it is scored on
(docs/league.md, "Cases")."""

from __future__ import annotations

from dataclasses import dataclass

OBJECTIVE = "distance_ratio"
"""Stop distance over the road's adhesion bound (plus the lock penalty): it asks nothing of a
law's internals, so a law with a target slip and one without compete on one scale."""

KNOWLEDGE = ("fixed", "oracle")
"""The league's road knowledge choices (`scenarios.road_knowledge`): one tuned target for every
road (the default: no vehicle knows its road's peak) or the road's own peak (the papers')."""


@dataclass(frozen=True)
class Case:
    """A held-out case: a road, parameters set to a value (`params`) and parameters scaled from
    the preset's value (`scale`, name -> factor)."""

    name: str
    road: str
    params: tuple[tuple[str, object], ...] = ()
    scale: tuple[tuple[str, float], ...] = ()


@dataclass(frozen=True)
class LeaguePlant:
    """One plant of the league: preset, the parameters of every run (`params`), what that mode
    is, the training roads and the held-out cases."""

    plant: str
    preset: str
    params: tuple[tuple[str, object], ...]
    mode: str
    training: tuple[str, ...]
    held_out: tuple[Case, ...]


def _mass(name: str, road: str, factor: float, dt_s: float | None = None) -> Case:
    """The preset's mass times `factor` (a heavier vehicle loads its wheels more, so their mode
    is faster: the step `dt_s` where RK4 needs a finer one, as `scenarios.abs_vehicle` says)."""
    params: tuple[tuple[str, object], ...] = () if dt_s is None else (("dt_s", dt_s),)
    return Case(name, road, params=params, scale=(("mass_kg", factor),))


WHEEL = LeaguePlant(
    plant="abs-wheel",
    preset="paper-derlsp-ao",
    params=(("ecu", "realistic"),),
    mode="the realistic ECU (docs/ecu.md: toothed sensor, reference-speed estimate, valves)",
    training=("dry-concrete", "wet-asphalt", "ice"),
    held_out=(
        Case("snow", "burckhardt-snow"),
        Case("cobblestone", "burckhardt-cobblestone-dry"),
        _mass("mass +20 %", "dry-concrete", 1.2),
        _mass("mass -20 %", "dry-concrete", 0.8),
        Case(
            "sensor noise",
            "dry-concrete",
            params=(
                ("sensor_spacing_error", 0.02),
                ("sensor_jitter_s", 2e-5),
                ("accel_noise_m_s2", 0.3),
            ),
        ),
    ),
)
"""The single wheel has no road whose friction changes during the stop, so the mu-jumps are
cases of the vehicle only."""

VEHICLE = LeaguePlant(
    plant="abs-vehicle",
    preset="paper-deffao",
    params=(),
    mode="the ideal controller (the vehicle has no realistic-ECU mode)",
    training=("dry-concrete", "wet-asphalt", "ice"),
    held_out=(
        Case(
            "mu-jump high to low",
            "mu-jump",
            params=(("first_surface", "dry-concrete"), ("second_surface", "ice")),
        ),
        Case(
            "mu-jump low to high",
            "mu-jump",
            params=(("first_surface", "ice"), ("second_surface", "dry-concrete")),
        ),
        Case("split-mu", "split-mu", params=(("steering", "driver"),)),
        _mass("mass +20 %", "dry-concrete", 1.2, dt_s=5e-4),
        _mass("mass -20 %", "dry-concrete", 0.8),
    ),
)
"""The vehicle's roads hold no Burckhardt curve, so snow and cobblestone are cases of the single
wheel only. On split-mu the driver model steers (with fixed steering any braking spins the car,
which scores the steering, not the law)."""

PLANTS = {p.plant: p for p in (WHEEL, VEHICLE)}
"""The league's plants by name."""
