"""The one seeding helper: every `numpy.random.Generator` and `SeedSequence` of the package.

A seed is an int >= 0, a `SeedSequence`, a `Generator` (used as is) or None (fresh entropy).
Child seeds are addressed, not drawn: child `i` of a root is `SeedSequence(root entropy,
spawn_key=root.spawn_key + (i,))`, which is what `root.spawn(...)[i]` returns, without mutating
the root; a study's run `i` and a run's side streams (F7's noise) are such children.
"""

from __future__ import annotations

import numpy as np

from chassistune.errors import InputError

SeedLike = int | np.integer | np.random.SeedSequence | np.random.Generator | None
RootSeed = int | np.integer | np.random.SeedSequence


def _check_int(seed: object) -> int:
    if isinstance(seed, int | np.integer) and not isinstance(seed, bool) and seed >= 0:
        return int(seed)
    raise InputError("seed", f"expected a non-negative integer, got {seed!r}")


def make_rng(seed: SeedLike) -> np.random.Generator:
    """A Generator from an int >= 0, a SeedSequence, None, or a Generator (returned as is)."""
    if isinstance(seed, np.random.Generator):
        return seed
    if seed is None or isinstance(seed, np.random.SeedSequence):
        return np.random.default_rng(seed)
    return np.random.default_rng(_check_int(seed))


def child_seed(root: RootSeed, index: int) -> np.random.SeedSequence:
    """Child `index` of `root` (an int >= 0 means `SeedSequence(root)`), the root left unchanged."""
    if not isinstance(root, np.random.SeedSequence):
        return np.random.SeedSequence(_check_int(root), spawn_key=(index,))
    return np.random.SeedSequence(
        root.entropy, spawn_key=(*root.spawn_key, index), pool_size=root.pool_size
    )


def int_seed(seed: np.random.SeedSequence) -> int:
    """A 32-bit integer seed drawn from `seed` (for APIs that take an int: road realizations)."""
    return int(seed.generate_state(1, np.uint32)[0])
