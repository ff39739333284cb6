"""`scenarios.warmup.collection_paused`: Python's garbage collector off while the warmup compiles,
back as it was afterwards (an exception included), the cycles collected at the end."""

from __future__ import annotations

import gc
import weakref

import pytest

from chassistune.scenarios.warmup import collection_paused


class _Cycle:
    def __init__(self) -> None:
        self.me = self


def test_the_collector_is_off_inside_and_back_on_after() -> None:
    assert gc.isenabled()
    with collection_paused():
        assert not gc.isenabled()
    assert gc.isenabled()


def test_an_exception_still_restores_the_collector() -> None:
    with pytest.raises(RuntimeError), collection_paused():
        raise RuntimeError("a case failed")
    assert gc.isenabled()


def test_a_collector_the_caller_turned_off_stays_off() -> None:
    gc.disable()
    try:
        with collection_paused():
            pass
        assert not gc.isenabled()
    finally:
        gc.enable()


def test_cycles_made_inside_are_collected_at_the_end() -> None:
    with collection_paused():
        refs = [weakref.ref(_Cycle()) for _ in range(1000)]
        assert all(r() is not None for r in refs)  # unreachable cycles, not collected yet
    assert all(r() is None for r in refs)
