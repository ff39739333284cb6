"""chassistune._rng: the seeding helper gives numpy's own streams, and refuses bad seeds."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune._rng import child_seed, int_seed, make_rng
from chassistune.errors import InputError


def test_make_rng_is_default_rng_for_ints_and_sequences() -> None:
    ss = np.random.SeedSequence(42)
    assert np.array_equal(make_rng(7).random(4), np.random.default_rng(7).random(4))
    assert np.array_equal(make_rng(ss).random(4), np.random.default_rng(ss).random(4))
    g = np.random.default_rng(1)
    assert make_rng(g) is g


@pytest.mark.parametrize("bad", [-1, 1.5, True, "3"])
def test_bad_seeds_are_input_errors(bad: object) -> None:
    with pytest.raises(InputError, match="seed"):
        make_rng(bad)  # type: ignore[arg-type]


def test_child_seed_equals_spawn_without_mutating_the_root() -> None:
    root = np.random.SeedSequence(11, spawn_key=(3,))
    spawned = np.random.SeedSequence(11, spawn_key=(3,)).spawn(2)
    for i in range(2):
        got = child_seed(root, i)
        assert got.spawn_key == spawned[i].spawn_key == (3, i)
        assert np.array_equal(got.generate_state(4), spawned[i].generate_state(4))
    assert root.n_children_spawned == 0
    assert child_seed(11, 3).spawn_key == root.spawn_key
    assert np.array_equal(child_seed(11, 3).generate_state(2), root.generate_state(2))


def test_int_seed_is_the_first_32_bit_word() -> None:
    ss = child_seed(5, 2)
    assert int_seed(ss) == int(ss.generate_state(1, np.uint32)[0])
