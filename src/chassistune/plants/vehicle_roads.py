"""Roads of the vehicle ABS (design.md 3.2, 3.3): uniform, `mu-jump` and `split-mu`, built by name
from the bilinear surfaces (derlsp-ao-abs Table 1, deffao-vehicle-abs Table 1).

Which surface is under wheel i follows its contact point's global position:
- `mu-jump`: the first surface until the contact point's global X reaches the jump, the second
  after; x_jump_m is measured from the front axle's start (global X_jump = lf + x_jump_m with the
  CG starting at X = 0);
- `split-mu`: the left surface under the car's left wheels, the right one under its right wheels
  (`split_by = "body"`, default: design.md 3.3's "by side"), or, with `split_by = "road"`, the left
  surface where the contact point's global Y >= split_y_m (0: the car starts centred on the split
  line) and the right one elsewhere;
- uniform roads: one surface everywhere.

Every road has `mu_scale` (default 1, positive; as the abs-wheel roads, `plants.tires`): it
multiplies both surfaces' whole mu-slip curves (mu_peak and mu_lock; the peak slip, hence the
target slip, stays), so that robust tuning can vary the grip (`tune --vary mu_scale=...`). The
resolved road carries the scaled surfaces: bounds, the kernel and the reference model read them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from chassistune.errors import InputError
from chassistune.params import as_dict, override
from chassistune.plants.roads import BILINEAR_ROADS
from chassistune.plants.tires import BilinearTire

ROAD_UNIFORM, ROAD_MU_JUMP, ROAD_SPLIT = 0, 1, 2
SPLIT_BY = ("body", "road")
_MU_SCALE = {"positive": True}


@dataclass(frozen=True)
class MuJumpParams:
    """Surfaces before and after the jump, and where it is (from the front axle's start)."""

    first_surface: str = "ice"
    second_surface: str = "dry-concrete"
    x_jump_m: float = field(default=25.0, metadata={"nonnegative": True})
    mu_scale: float = field(default=1.0, metadata=_MU_SCALE)


@dataclass(frozen=True)
class SplitMuParams:
    """Surfaces left and right: by the wheel's side of the car (`split_by = "body"`), or by the
    contact point's global Y against the split line y = split_y_m (`split_by = "road"`)."""

    left_surface: str = "dry-concrete"
    right_surface: str = "ice"
    split_by: str = "body"
    split_y_m: float = 0.0
    mu_scale: float = field(default=1.0, metadata=_MU_SCALE)


@dataclass(frozen=True)
class VehicleRoad:
    """A resolved road: its kind, its two surfaces (equal on uniform roads) and geometry."""

    name: str
    kind: int
    surface_names: tuple[str, str]
    surfaces: tuple[BilinearTire, BilinearTire]
    x_jump_m: float = 0.0
    split_by: str = "body"
    split_y_m: float = 0.0

    def description(self) -> str:
        a, b = self.surface_names
        if self.kind == ROAD_MU_JUMP:
            return f"{a} for {self.x_jump_m:g} m from the front axle's start, then {b}"
        if self.kind == ROAD_SPLIT:
            return f"{a} left of y = {self.split_y_m:g} m, {b} right"
        return a


def road_names() -> dict[str, str]:
    """Road name -> description."""
    out = {
        n: f"uniform bilinear slip_opt={s}, mu_peak={h}, mu_lock={g}: {d}"
        for n, (s, h, g, d) in BILINEAR_ROADS.items()
    }
    out["mu-jump"] = (
        "docking road: ice for 25 m from the front axle's start, then dry concrete "
        "(first_surface, second_surface, x_jump_m)"
    )
    out["split-mu"] = (
        "split road: dry concrete left, ice right (left_surface, right_surface, split_y_m)"
    )
    return out


def surface(name: str, field_name: str, mu_scale: float = 1.0) -> BilinearTire:
    """A bilinear surface by name with its curve scaled by mu_scale, or InputError naming the
    field."""
    if name not in BILINEAR_ROADS:
        raise InputError(
            field_name, f"unknown surface {name!r} (known: {', '.join(BILINEAR_ROADS)})"
        )
    s, h, g, _ = BILINEAR_ROADS[name]
    return scaled(BilinearTire(s, h, g), mu_scale)


def scaled(tire: BilinearTire, mu_scale: float) -> BilinearTire:
    """The surface with mu_peak and mu_lock multiplied by mu_scale (its own and the road's)."""
    scale = tire.mu_scale * mu_scale
    return BilinearTire(tire.slip_opt, tire.mu_peak * scale, tire.mu_lock * scale)


def make_road(
    name: str, values: Mapping[str, object]
) -> tuple[VehicleRoad, set[str], dict[str, object]]:
    """The road `name` with its parameter overrides; returns (road, names used, params echo)."""
    if name == "mu-jump":
        jump, used = override(MuJumpParams(), values)
        names, pair = _surfaces(jump, "first_surface", "second_surface")
        road = VehicleRoad(name, ROAD_MU_JUMP, names, pair, x_jump_m=jump.x_jump_m)
        return road, used, as_dict(jump)
    if name == "split-mu":
        split, used = override(SplitMuParams(), values)
        if split.split_by not in SPLIT_BY:
            raise InputError("params.split_by", f"must be body or road, got {split.split_by!r}")
        names, pair = _surfaces(split, "left_surface", "right_surface")
        road = VehicleRoad(
            name, ROAD_SPLIT, names, pair, split_by=split.split_by, split_y_m=split.split_y_m
        )
        return road, used, as_dict(split)
    if name not in BILINEAR_ROADS:
        raise InputError(
            "road", f"unknown road {name!r} for abs-vehicle (known: {', '.join(road_names())})"
        )
    tire, used = override(surface(name, "road"), values)
    curve = scaled(tire, 1.0)
    return VehicleRoad(name, ROAD_UNIFORM, (name, name), (curve, curve)), used, as_dict(tire)


def _surfaces(
    params: MuJumpParams | SplitMuParams, first: str, second: str
) -> tuple[tuple[str, str], tuple[BilinearTire, BilinearTire]]:
    """A two-surface road's surface names (fields `first`, `second` of params) and its surfaces
    scaled by params.mu_scale."""
    names = (getattr(params, first), getattr(params, second))
    return names, (
        surface(names[0], f"params.{first}", params.mu_scale),
        surface(names[1], f"params.{second}", params.mu_scale),
    )
