"""Which kernels numba compiles, as it compiles them: one stderr line before each kernel that is
not in the disk cache yet, and the record of what `chassistune warmup` compiled.

numba fires its "numba:compile" event only after a cache miss (numba.core.dispatcher), for the
very function and argument types about to be compiled: no guess from the cache folder's files.
A kernel's helpers compile inside its own event and are counted as part of it.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

from numba.core import event

COMPILE_CPU_S = {
    "abs_vehicle_kernel": 58,
    "abs_wheel_ecu_kernel": 41,
    "abs_wheel_kernel": 40,
    "quarter_car_kernel": 12,
    "lyapunov": 7,
    "discrete": 2,
}
"""CPU seconds numba takes to compile a kernel of each module (the single wheel's one entry
point, with every tire law and integration method; the realistic ECU kernel, whose step loop
is compiled once per tire law; the vehicle's lane loop with its straight and general passes and
its law ticks, the Magic Formula and the lagged slips; the C export's replay of the discrete
laws, which loads the ECU's law dispatch), measured with `time.process_time` around each
compilation on a fresh cache, the kernels one after another in one process (2026-11-29, 2 cores,
nothing else running): about the wall time on an idle core, several times that while other work
shares it."""

OTHER_CPU_S = 3
"""About the CPU seconds of any other compiled function (a fuzzy surface, a C export replay)."""


def kernel_name(dispatcher: Any) -> str:
    """`module.function` of a compiled function (numba's dispatcher)."""
    func = dispatcher.py_func
    return f"{func.__module__.rsplit('.', 1)[-1]}.{func.__qualname__.rsplit('.', 1)[-1]}"


def estimate_cpu_s(name: str) -> float:
    """The measured compile time of kernel `name` (`kernel_name`), else `OTHER_CPU_S`."""
    return COMPILE_CPU_S.get(name.split(".", 1)[0], OTHER_CPU_S)


class CompileLog(event.Listener):
    """The functions numba compiles in this process, each with its CPU seconds (`done`);
    `on_compile(name)` is called as each starts."""

    def __init__(self, on_compile: Callable[[str], None] | None = None) -> None:
        self.on_compile = on_compile
        self.done: list[tuple[str, float]] = []
        self._depth = 0
        self._name = ""
        self._cpu0 = 0.0

    def on_start(self, ev: Any) -> None:
        self._depth += 1
        if self._depth == 1:
            self._name = kernel_name(ev.data["dispatcher"])
            self._cpu0 = time.process_time()
            if self.on_compile is not None:
                self.on_compile(self._name)

    def on_end(self, ev: Any) -> None:
        self._depth -= 1
        if self._depth == 0:
            self.done.append((self._name, time.process_time() - self._cpu0))


def notice(name: str) -> str:
    """The line said before compiling kernel `name`."""
    from chassistune._numba_cache import numba_cache_is_temporary

    kept = (
        "not kept: the cache is a temporary folder"
        if numba_cache_is_temporary()
        else f"cached in {os.environ.get('NUMBA_CACHE_DIR', '')}"
    )
    return (
        f"chassistune: compiling {name} (first use: about {estimate_cpu_s(name):.0f} s on an "
        f"idle core, longer under load; {kept}; `chassistune warmup` compiles every kernel)"
    )


@contextmanager
def recording(log: CompileLog) -> Iterator[None]:
    """While inside, `log` sees every compilation of this process."""
    with event.install_listener("numba:compile", log):
        yield


@contextmanager
def announcing(echo: Callable[[str], None]) -> Iterator[None]:
    """While inside, `echo` the `notice` of every kernel this process compiles."""
    with recording(CompileLog(lambda name: echo(notice(name)))):
        yield
