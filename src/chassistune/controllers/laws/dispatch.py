"""The one dispatch of the control laws in the kernels: `law_start`, `tick_pass`, `law_sampled`,
`law_initial_state` in the ideal kernels (whose vector loops take each law's continuous form
from `continuous_groups`), `law_ecu_step`, `law_ecu_schedule`, `law_ecu_rate` in the realistic ECU.

Each is a numba overload whose implementation is generated from the registry when a kernel is
compiled: an if-chain over the registered kinds, each branch the law's own form (`Law.forms`:
start) inlined into it. The chain compiles as a function of its own (inlining it whole at
numba's IR level trips numba's SSA checks), with the kernel's options: no reference counting
under an entry point compiled without it. A kind no law holds runs no law: its held values are
NaN (in the ECU: its command), so that the run diverges (the scenarios refuse unknown names
before a kernel runs).

A sampled law's tick runs in a kernel's tick pass (`tick_pass`): the kernel builds, per law, a
function of its own that loops over what is due (lanes, wheels) with the law's tick inlined in
it, and the pass picks that function by kind once per call. A tick is a small update with many
arguments (a fuzzy law's table alone unpacks into about 50 scalars): called once per lane it
costs more than its arithmetic; inlined into the kernel's lane loop it makes that loop several
times longer to compile.

The first argument `laws_key` is `registry.fingerprint()` as an integer constant of the kernel's
entry point (a closure variable): numba keys its disk cache on it, and the overloads are typed
on its literal value (`prefer_literal`), so that a law registered or changed, in this process
or another, compiles the kernel anew instead of reusing a dispatch without it.
"""

from __future__ import annotations

import functools
import hashlib
import inspect
from collections.abc import Callable
from typing import Any

import numpy as np
from numba import njit, types
from numba.core.errors import TypingError
from numba.extending import overload

from chassistune.controllers.laws import registry
from chassistune.controllers.laws.forms import ECU_SIGNALS, FORM
from chassistune.controllers.laws.held_pid import HELD_PID

_NAN4 = (np.nan, np.nan, np.nan, np.nan)


def law_start(laws_key, kind, g, g0, c):
    """The held values (u0, kp, ki, kd) of law `kind` at a run's start (in compiled code)."""
    raise NotImplementedError("law_start runs in compiled code only")


def law_sampled(laws_key, kind):
    """Whether law `kind` has a tick (in compiled code)."""
    raise NotImplementedError("law_sampled runs in compiled code only")


def law_initial_state(laws_key, kind, target):
    """The continuous state of law `kind` at a run's start, padded with zeros to
    `registry.CONTINUOUS` floats (in compiled code)."""
    raise NotImplementedError("law_initial_state runs in compiled code only")


def law_ecu_step(laws_key, kind, state, inputs, sig, params, table, grid):
    """The ECU command u of law `kind` at a tick, its inputs taken from the signals `sig`
    (`forms.ECU_SIGNALS`); `state` is updated in place (in compiled code). A call of
    `ecu_step(laws_key)`, compiled once for every caller."""
    raise NotImplementedError("law_ecu_step runs in compiled code only")


def _ecu_chain(laws_key, kind, state, inputs, sig, params, table, grid):
    """`law_ecu_step`'s if-chain over the registered kinds (in compiled code)."""
    raise NotImplementedError("_ecu_chain runs in compiled code only")


def law_ecu_schedule(laws_key, kind, base, params, f):
    """Write law `kind`'s parameters `base` into `params`, its scheduled ones times f (in
    compiled code)."""
    raise NotImplementedError("law_ecu_schedule runs in compiled code only")


def law_ecu_rate(laws_key, kind):
    """Whether law `kind`'s ECU command is a pressure rate (in compiled code)."""
    raise NotImplementedError("law_ecu_rate runs in compiled code only")


def _kinds() -> list[registry.Law]:
    return [registry.by_kind(k) for k in range(len(registry.names()))]


def continuous_form(law: registry.Law) -> registry.ContinuousForm:
    """The law's continuous form (the held PID where it declares none)."""
    return HELD_PID if law.continuous is None else law.continuous


def continuous_groups() -> list[tuple[registry.ContinuousForm, bool, tuple[int, ...]]]:
    """(continuous form, sampled, kinds) of the registered laws, grouped: a kernel compiles one
    vector loop per group (the held PID unsampled first: what a kind no law holds runs)."""
    groups: dict[tuple[int, bool], tuple[registry.ContinuousForm, bool, list[int]]] = {
        (id(HELD_PID), False): (HELD_PID, False, [])
    }
    for k, law in enumerate(_kinds()):
        form, sampled = continuous_form(law), law.forms()[1] is not None
        groups.setdefault((id(form), sampled), (form, sampled, []))[2].append(k)
    return [(form, sampled, tuple(kinds)) for form, sampled, kinds in groups.values()]


_RATES: dict[int, registry.ContinuousForm] = {}
"""The continuous forms named so far, by key (`form_key`)."""


def form_key(form: registry.ContinuousForm) -> int:
    """The integer naming `form` in compiled code (`law_rate`): a digest of its state and of the
    source of the module that builds it, so that a kernel numba cached on disk for one form is
    never loaded for another (in this process or the next)."""
    module = inspect.getmodule(form.forms)
    source = inspect.getsource(module) if module is not None else ""
    key = int(hashlib.sha1(repr((form.state, source)).encode()).hexdigest()[:15], 16)
    _RATES[key] = form
    return key


def rate_groups() -> list[tuple[int, tuple[int, ...]]]:
    """(form key, kinds) of the registered laws by continuous form alone (sampled or not), the
    held PID's first (`continuous_groups`): a kernel integrating every law with one method
    compiles its passes once per group."""
    groups: dict[int, list[int]] = {}
    for form, _, kinds in continuous_groups():
        groups.setdefault(form_key(form), []).extend(kinds)
    return [(key, tuple(kinds)) for key, kinds in groups.items()]


def law_rate(form, e, x, held, c, n_filter, at_max, at_min):
    """(u, dx) of the continuous form of key `form` (`form_key`, a literal) at slip error e, its
    state x and rates dx padded with zeros to `registry.CONTINUOUS` floats (in compiled code)."""
    raise NotImplementedError("law_rate runs in compiled code only")


@overload(law_rate, prefer_literal=True, inline="always")
def _law_rate(form, e, x, held, c, n_filter, at_max, at_min):
    if not isinstance(form, types.IntegerLiteral):
        raise TypingError("the continuous form's key must be a compile-time constant")
    continuous = _RATES[form.literal_value]
    rate = continuous.forms()[1]
    n = len(continuous.state)
    if n == registry.CONTINUOUS:

        def impl(form, e, x, held, c, n_filter, at_max, at_min):
            return rate(e, x, held, c, n_filter, at_max, at_min)

        return impl
    pad = (0.0,) * (registry.CONTINUOUS - n)

    def padded(form, e, x, held, c, n_filter, at_max, at_min):
        u, dx = rate(e, x[:n], held, c, n_filter, at_max, at_min)
        return u, dx + pad

    return padded


def _form_call(run: Any, key: int) -> Callable[..., Any]:
    @njit(**_LINK)
    def call(kind, args):
        return run(key, args)

    return call


def _form_link(kinds: tuple[int, ...], run: Any, key: int, rest: Any) -> Callable[..., Any]:
    @njit(**_FORM_LINK)
    def link(kind, args):
        hit = False
        for k in kinds:
            hit |= kind == k
        if hit:
            return run(key, args)
        return rest(kind, args)

    return link


def by_continuous_form(run: Any) -> Callable[..., Any]:
    """`pass(laws_key, kind, args)` in compiled code: `run(form, args)` with `form` the key
    (`form_key`, a literal) of the continuous form of law `kind`; a kind no law holds runs the
    held PID's (whose held values are then NaN: the run diverges). One branch per continuous
    form of the registered laws (`rate_groups`), so that `run` compiles once per form."""

    def by_form(laws_key, kind, args):
        raise NotImplementedError("a pass by continuous form runs in compiled code only")

    @overload(by_form, prefer_literal=True, inline="always")
    def _by_form(laws_key, kind, args):
        _literal(laws_key)
        groups = rate_groups()
        chain = _form_call(run, groups[0][0])
        for key, kinds in reversed(groups[1:]):
            chain = _form_link(kinds, run, key, chain)

        def impl(laws_key, kind, args):
            return chain(kind, args)

        return impl

    return by_form


@njit(**FORM)
def _no_start(kind, g, g0, c):
    return _NAN4


@njit(**FORM)
def _at_rest(g, g0, c):
    return 0.0, 0.0, 0.0, 0.0


_NAN_STATE = (np.nan,) * registry.CONTINUOUS


@njit(**FORM)
def _no_initial_state(kind, target):
    return _NAN_STATE


@njit(**FORM)
def _no_ecu_step(kind, state, inputs, sig, params, table, grid):
    return np.nan


@njit(**FORM)
def _no_schedule(kind, base, params, f):
    return None


_LINK = {**FORM, "cache": False}
"""A link of a chain is built per compilation (a closure over the law's form): not cached."""

_FORM_LINK = {**_LINK, "inline": "never"}
"""A link of a pass's chain by continuous form is a call (inlined, its branches trip numba's
IR checks); the pass it calls is a whole vector loop. The chain's last, without a branch, is
inlined (`_LINK`): each call level links in and optimizes the whole pass again."""


def _start_link(k: int, start: Any, rest: Any) -> Callable[..., Any]:
    @njit(**_LINK)
    def link(kind, g, g0, c):
        if kind == k:
            return start(g, g0, c)
        return rest(kind, g, g0, c)

    return link


def _initial_link(k: int, initial: Any, pad: tuple[float, ...], rest: Any) -> Callable[..., Any]:
    @njit(**_LINK)
    def link(kind, target):
        if kind == k:
            return initial(target) + pad
        return rest(kind, target)

    return link


def _ecu_link(k: int, step: Any, picks: tuple[int, ...], rest: Any) -> Callable[..., Any]:
    @njit(**{**_LINK, "inline": "never"})
    def call(state, inputs, params, table, grid):
        return step(state, inputs, params, table, grid)

    @njit(**_LINK)
    def link(kind, state, inputs, sig, params, table, grid):
        if kind == k:
            for j in range(len(picks)):
                inputs[j] = sig[picks[j]]
            return call(state, inputs, params, table, grid)
        return rest(kind, state, inputs, sig, params, table, grid)

    return link


def _schedule_link(k: int, scaled: tuple[int, ...], rest: Any) -> Callable[..., Any]:
    @njit(**_LINK)
    def link(kind, base, params, f):
        if kind == k:
            for j in range(len(scaled)):
                params[scaled[j]] = base[scaled[j]] * f
        else:
            rest(kind, base, params, f)

    return link


def _literal(laws_key: Any) -> None:
    if not isinstance(laws_key, types.IntegerLiteral):
        raise TypingError("laws_key must be a compile-time constant (the registry's fingerprint)")


@overload(law_start, prefer_literal=True)
def _law_start(laws_key, kind, g, g0, c):
    _literal(laws_key)
    chain = _no_start
    for k, law in reversed(list(enumerate(_kinds()))):
        start = law.forms()[0]
        chain = _start_link(k, _at_rest if start is None else start, chain)

    def impl(laws_key, kind, g, g0, c):
        return chain(kind, g, g0, c)

    return impl


@njit(**_LINK)
def _no_pass(kind, args):
    return None


def _pass_link(k: int, run: Any, rest: Any) -> Callable[..., Any]:
    @njit(**_LINK)
    def link(kind, args):
        if kind == k:
            run(*args)
        else:
            rest(kind, args)

    return link


def tick_pass(each: Callable[[Any], Any]) -> Callable[..., None]:
    """A kernel's tick pass, `run(laws_key, kind, args)` in compiled code: `each(tick)(*args)`
    for the law of kind `kind`, `tick` its tick (`Law.forms`), nothing for a kind without one.
    `each(tick)` builds the law's pass, a function compiled on its own with `tick` inlined (a
    closure over it), once per tick: the kernel's lane loop makes one call per pass."""

    def run(laws_key, kind, args):
        raise NotImplementedError("a tick pass runs in compiled code only")

    @overload(run, prefer_literal=True, inline="always")
    def _run(laws_key, kind, args):
        _literal(laws_key)
        chain = _no_pass
        for k, law in reversed(list(enumerate(_kinds()))):
            tick = law.forms()[1]
            if tick is not None:
                chain = _pass_link(k, each(tick), chain)

        def impl(laws_key, kind, args):
            chain(kind, args)

        return impl

    return run


@overload(law_sampled, prefer_literal=True)
def _law_sampled(laws_key, kind):
    _literal(laws_key)
    sampled = tuple(k for k, law in enumerate(_kinds()) if law.forms()[1] is not None)

    def impl(laws_key, kind):
        hit = False
        for k in sampled:
            hit |= kind == k
        return hit

    return impl


@overload(law_initial_state, prefer_literal=True)
def _law_initial_state(laws_key, kind, target):
    _literal(laws_key)
    chain = _no_initial_state
    for k, law in reversed(list(enumerate(_kinds()))):
        form = continuous_form(law)
        pad = (0.0,) * (registry.CONTINUOUS - len(form.state))
        chain = _initial_link(k, form.forms()[0], pad, chain)

    def impl(laws_key, kind, target):
        return chain(kind, target)

    return impl


@overload(_ecu_chain, prefer_literal=True)
def _ecu_chain_impl(laws_key, kind, state, inputs, sig, params, table, grid):
    _literal(laws_key)
    chain = _no_ecu_step
    for k, law in reversed(list(enumerate(_kinds()))):
        if law.ecu is not None:
            picks = tuple(ECU_SIGNALS[n] for n in law.ecu_inputs)
            chain = _ecu_link(k, law.ecu.step(), picks, chain)

    def impl(laws_key, kind, state, inputs, sig, params, table, grid):
        return chain(kind, state, inputs, sig, params, table, grid)

    return impl


_ECU_STEP: dict[str, Any] = {"cache": True, "nogil": True, "error_model": "numpy", "_nrt": False}


@functools.cache
def ecu_step(laws_key: int) -> Any:
    """`law_ecu_step` of the laws named by `laws_key` as a function of its own, cached on disk
    (keyed on `laws_key`, a closure variable) and never inlined: the realistic ECU kernel and
    the C export's replay (`controllers.discrete`) call this one compilation of every law's
    ECU form instead of each compiling its own. Compiled without reference counting, as the
    ECU kernel is (it allocates nothing)."""

    def ecu_step(kind, state, inputs, sig, params, table, grid):
        return _ecu_chain(laws_key, kind, state, inputs, sig, params, table, grid)

    return njit(**_ECU_STEP)(ecu_step)


@overload(law_ecu_step, prefer_literal=True, inline="always")
def _law_ecu_step(laws_key, kind, state, inputs, sig, params, table, grid):
    _literal(laws_key)
    step = ecu_step(laws_key.literal_value)

    def impl(laws_key, kind, state, inputs, sig, params, table, grid):
        return step(kind, state, inputs, sig, params, table, grid)

    return impl


@overload(law_ecu_schedule, prefer_literal=True)
def _law_ecu_schedule(laws_key, kind, base, params, f):
    _literal(laws_key)
    chain = _no_schedule
    for k, law in reversed(list(enumerate(_kinds()))):
        if law.ecu is not None and law.ecu.scheduled and law.discrete is not None:
            scaled = tuple(law.discrete.params.index(n) for n in law.ecu.scheduled)
            chain = _schedule_link(k, scaled, chain)

    def impl(laws_key, kind, base, params, f):
        for j in range(base.shape[0]):
            params[j] = base[j]
        chain(kind, base, params, f)

    return impl


@overload(law_ecu_rate, prefer_literal=True)
def _law_ecu_rate(laws_key, kind):
    _literal(laws_key)
    rates = tuple(k for k, law in enumerate(_kinds()) if law.ecu is not None and law.ecu.rate)

    def impl(laws_key, kind):
        hit = False
        for k in rates:
            hit |= kind == k
        return hit

    return impl
