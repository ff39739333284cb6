"""The registry of ABS control laws: a law's kind is its position in registration order.

A leaf: it knows no law. Each law is one module of `controllers.laws` (a `Law` declaring its
specs per plant family, its compiled forms, its discrete form and its C), registered once;
kernels and scenarios number laws through `kind`, look them up through `get` and run them
through one dispatch (`controllers.laws.dispatch`), so that no module keeps a list of law names.
An unknown name or kind fails loudly (InputError naming the field, or ValueError for a kind no
law holds), never runs another law.
"""

from __future__ import annotations

import hashlib
import inspect
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, TypeVar

from chassistune._registry import Registry
from chassistune.controllers.specs import ControllerSpec

ABS_WHEEL = "abs-wheel"
ABS_VEHICLE = "abs-vehicle"


@dataclass(frozen=True)
class DiscreteLaw:
    """A law's discrete form (what an ECU runs and `export` ships, `controllers.discrete`): the
    names of its inputs, parameters and state entries, in vector order; how many outputs it
    reads from the rule base's lookup table (0: no table); the form, named."""

    controller: str
    inputs: tuple[str, ...]
    params: tuple[str, ...]
    state: tuple[str, ...]
    table_outputs: int
    form: str


@dataclass(frozen=True)
class CForm:
    """A law's C99 text for `export`: its equations (printed in controller.h), `ct_step` with any
    static helpers it needs (`{k}` names the table of rule-base output k), the shared helper
    blocks it calls, and whether a discrete decision (a phase) makes FMA contraction unsafe."""

    equations: tuple[str, ...]
    step: str
    helpers: tuple[str, ...] = ()
    switching: bool = False


@dataclass(frozen=True)
class EcuForm:
    """A law's form in the realistic ECU (`sim.abs_wheel_ecu_kernel`, docs/ecu.md): `step()`
    builds its numba step `u = step(state, inputs, params, table, grid)` (the signature of
    `controllers.discrete`), fed the ECU signals (`forms.ECU_SIGNALS`) its law reads
    (`Law.ecu_inputs`: its discrete form's inputs, or, for a law without one, those named in
    `inputs`), in that order; the parameters named in `scheduled` (of its discrete form's
    `params`) scale with the speed schedule; `rate`: the command is a pressure rate
    (three-state valves: a duty pulse), else a switching command."""

    step: Callable[[], Any]
    inputs: tuple[str, ...] = ()
    scheduled: tuple[str, ...] = ()
    rate: bool = False


@dataclass(frozen=True)
class ContinuousForm:
    """A law's continuous form in the ideal kernels, integrated with the plant: its state, by
    name (at most `CONTINUOUS` slots), and `forms()`, which builds its numba functions
    `initial(target) -> x` (its state at a run's start, where the slip error is the target
    slip) and `rate(e, x, held, c, n_filter, at_max, at_min) -> (u, dx)`: the command u and the
    state's rates at slip error e, with the held values (`forms.HELD`), the controller vector
    c, the plant's derivative filter coefficient N and whether the pressure sits at q_max or 0
    (`forms` names the arguments). x and dx are tuples of len(state) floats."""

    state: tuple[str, ...]
    forms: Callable[[], tuple[Any, Any]]


@dataclass(frozen=True)
class Law:
    """One control law: its specs (one per plant family it runs on), its sampled forms for the
    ideal kernels, its discrete form (what an ECU runs and `export` ships; None without one),
    its form in the realistic ECU (None: it does not run there), its C text and how many outputs
    it reads from a rule base (0: none).

    The kernels' forms are numba functions that `forms()` builds on first use (numba is heavy
    to import; the specs are not), `controllers.laws.forms` names their arguments: `start(g,
    g0, c) -> held`, the held values (u0, kp, ki, kd) of the continuous PID at the start of a
    run (None: all zero, the law at rest), and `tick(sig, held, mem, g, g0, c, table, ts,
    first) -> (held, mem)`, the update at each sample instant (None: the law is not sampled),
    with `mem` the law's memory (`state`, in `slots("memory")` slots, zero at the start).
    `continuous`: its continuous form (None: the continuous PID with the held values,
    `controllers.laws.held_pid.HELD_PID`).
    """

    name: str
    specs: tuple[ControllerSpec, ...]
    forms: Callable[[], tuple[Any, Any]]
    state: tuple[str, ...] = ()
    discrete: DiscreteLaw | None = None
    ecu: EcuForm | None = None
    c: CForm | None = None
    rulebase_outputs: int = 0
    continuous: ContinuousForm | None = None
    source: str = ""
    """Where the law's equations come from (a paper and its equation, a product, or ours)."""
    needs_target: bool = True
    """Whether it regulates to a target slip, which the road knowledge supplies (the road's
    optimum, `oracle`, or a fixed one); False: it needs no knowledge of the road."""

    def spec(self, plant: str) -> ControllerSpec | None:
        """The law's spec on `plant`, or None when it does not run there."""
        return next((s for s in self.specs if s.plant == plant), None)

    @property
    def ecu_inputs(self) -> tuple[str, ...]:
        """The ECU signals its ECU form reads, in order: its discrete form's inputs (the one
        declaration), or the ECU form's own for a law without a discrete form; () without an
        ECU form."""
        if self.ecu is None:
            return ()
        return self.discrete.inputs if self.discrete is not None else self.ecu.inputs


CONTINUOUS = 2
"""Slots of a law's continuous state in the kernels' lanes (the largest `ContinuousForm.state`):
the ideal wheel kernel's vector loop carries them as two values of its state tuple."""

_LAWS: Registry[Law] = Registry("controller")
_DIGESTS: dict[str, str] = {}
_SLOTS: dict[str, int] = {}
"""The slot counts the kernels' layouts were sized with (`slots`), by what they hold."""


def _needs(law: Law) -> dict[str, int]:
    """The slots `law` needs, by what they hold (`slots`)."""
    return {
        "memory": len(law.state),
        "ecu_inputs": len(law.ecu_inputs),
        "discrete_state": 0 if law.discrete is None else len(law.discrete.state),
    }


def slots(what: str) -> int:
    """The most slots any registered law needs of `what`: `memory` (`Law.state`, the kernels'
    lanes), `ecu_inputs` (`Law.ecu_inputs`, the ECU kernel's lanes), `discrete_state`
    (`DiscreteLaw.state`, the state vector of `controllers.discrete`). Fixed at the first ask:
    a kernel's layout asks on import, after `controllers.laws` registered the built-in laws,
    and a law registered later that needs more is refused."""
    if what not in _SLOTS:
        _SLOTS[what] = max(_needs(get(n))[what] for n in names())
    return _SLOTS[what]


def register(law: Law) -> Law:
    """Add `law` under its name (its kind: the next number); a name registered twice is refused."""
    if any(s.name != law.name for s in law.specs):
        raise ValueError(f"law {law.name!r} declares a spec of another name")
    if not law.source:
        raise ValueError(f"law {law.name!r} does not say where its equations come from (source)")
    for what, need in _needs(law).items():
        if need > _SLOTS.get(what, need):
            raise ValueError(f"law {law.name!r} needs {need} {what} slots (at most {_SLOTS[what]})")
    if law.continuous is not None and not 0 < len(law.continuous.state) <= CONTINUOUS:
        raise ValueError(f"law {law.name!r} integrates 1 to {CONTINUOUS} continuous states")
    if law.ecu is not None and law.ecu.inputs and law.discrete is not None:
        raise ValueError(
            f"law {law.name!r} names its ECU inputs twice (its discrete form declares them)"
        )
    if law.ecu is not None and not law.ecu_inputs:
        raise ValueError(f"law {law.name!r} reads no ECU input")
    _LAWS.register(law.name, law)
    module = inspect.getmodule(law.forms)
    source = inspect.getsource(module) if module is not None else law.name
    _DIGESTS[law.name] = hashlib.sha1(source.encode()).hexdigest()
    return law


def unregister(name: str) -> None:
    """Remove the law `name` (a test registering a temporary law cleans up with it); a law
    registered after it would change kind, so only the last one may go."""
    if _LAWS.names()[-1:] != [name]:
        raise ValueError(f"only the last registered law may be removed, not {name!r}")
    _LAWS.unregister(name)
    del _DIGESTS[name]


def fingerprint() -> str:
    """Names the registered laws and their modules' sources: a compiled kernel that dispatches
    over the registry is valid while it is unchanged (kernels key their disk cache on it)."""
    return hashlib.sha1(repr([(n, _DIGESTS[n]) for n in names()]).encode()).hexdigest()[:16]


T = TypeVar("T")


def per_fingerprint(build: Callable[[int], T]) -> Callable[[], T]:
    """A memo of code compiled over the registry: the returned function gives `build(key)` for
    the laws registered now, built once per `fingerprint` (key: the fingerprint as an integer,
    the `laws_key` constant on which a compiled law dispatch is typed and numba keys its disk
    cache)."""
    built: dict[str, T] = {}

    def for_laws_now() -> T:
        key = fingerprint()
        if key not in built:
            built[key] = build(int(key[:15], 16))
        return built[key]

    return for_laws_now


def names() -> list[str]:
    """Every law, in registration (kind) order."""
    return _LAWS.names()


def get(name: str, where: str = "") -> Law:
    """The law `name`, or InputError (field `controller`) listing the known laws."""
    return _LAWS.get(name, where)


def kind(name: str) -> int:
    """The law's kind: its position in registration order (InputError for an unknown name)."""
    get(name)
    return names().index(name)


def by_kind(k: int) -> Law:
    """The law of kind k; ValueError for a kind no law holds."""
    all_names = names()
    if not 0 <= k < len(all_names):
        raise ValueError(f"no control law of kind {k} (kinds 0 .. {len(all_names) - 1})")
    return get(all_names[k])


def for_plant(plant: str) -> list[ControllerSpec]:
    """The specs of every law that runs on `plant`, in kind order."""
    specs = (get(n).spec(plant) for n in names())
    return [s for s in specs if s is not None]
