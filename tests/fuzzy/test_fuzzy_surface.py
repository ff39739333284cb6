"""Compiled lookup surfaces against exact inference."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune.errors import InputError
from chassistune.fuzzy import (
    CompiledSurface,
    RuleBase,
    compile_rulebase,
    compiled,
    evaluate,
    load_rulebase,
    surface_lookup,
    surface_value,
)

TOLERANCE = 1e-3  # of the output range


def test_surface_agrees_with_exact_inference(builtin: RuleBase) -> None:
    cs = compiled(builtin)
    lo = np.array([v.universe[0] for v in builtin.inputs])
    hi = np.array([v.universe[1] for v in builtin.inputs])
    points = np.random.default_rng(99).uniform(lo, hi, (2000, 2))
    err = (
        np.abs(cs.lookup(points[:, 0], points[:, 1]) - evaluate(builtin, points)) / cs.output_spans
    )
    print(f"{builtin.name}: max surface error {err.max():.2e}, tables {cs.nbytes / 1e6:.1f} MB")
    assert err.max() < TOLERANCE


def test_surface_is_exact_on_grid_nodes_and_clips(builtin: RuleBase) -> None:
    cs = compiled(builtin)
    i = np.array([0, 7, cs.n[0] - 1])
    j = np.array([cs.n[1] - 1, 3, 0])
    x0, x1 = cs.grid_lo[0] + i * cs.grid_step[0], cs.grid_lo[1] + j * cs.grid_step[1]
    np.testing.assert_allclose(
        cs.lookup(x0, x1), evaluate(builtin, np.stack([x0, x1], 1)), atol=1e-12
    )
    lo0, hi1 = builtin.inputs[0].universe[0], builtin.inputs[1].universe[1]
    np.testing.assert_array_equal(cs.lookup(lo0 - 5.0, hi1 + 1e9), cs.lookup(lo0, hi1))
    assert np.isnan(cs.lookup(np.nan, 0.0)).all()


def test_grid_is_aligned_with_the_set_knots(builtin: RuleBase) -> None:
    cs = compiled(builtin)
    for axis, var in enumerate(builtin.inputs):
        for s in var.sets:
            for knot in s.knots:
                steps = (knot - cs.grid_lo[axis]) / cs.grid_step[axis]
                assert abs(steps - round(steps)) < 1e-9
        assert cs.grid_lo[axis] + (cs.n[axis] - 1) * cs.grid_step[axis] == pytest.approx(
            var.universe[1]
        )


def test_table_layout() -> None:
    cs = compiled(load_rulebase("deffao"))
    values, block, block_start, block_r, fine, lo0, step0, lo1, step1 = cs.table
    n0, n1 = cs.n
    assert values.shape == (n0, n1, 3) and values.dtype == np.float64 and values.flags.c_contiguous
    assert block.shape == (n0 - 1, n1 - 1) and block.dtype == np.int32
    refined = block[block >= 0]
    assert np.array_equal(np.sort(refined), np.arange(block_r.size))
    assert fine.size == int(np.sum(3 * (block_r + 1) ** 2))
    # A refined block's corner nodes are the coarse nodes of its cell.
    i, j = np.argwhere(block >= 0)[0]
    b, r = block[i, j], block_r[block[i, j]]
    sub = fine[block_start[b] : block_start[b] + 3 * (r + 1) ** 2].reshape(r + 1, r + 1, 3)
    np.testing.assert_allclose(sub[0, 0], values[i, j], atol=1e-12)
    np.testing.assert_allclose(sub[r, r], values[i + 1, j + 1], atol=1e-12)
    assert (lo0, lo1) == (-3.0, -3.0) and step0 == step1 == pytest.approx(6.0 / (n0 - 1))


def test_compiled_is_cached_and_compile_checks_inputs() -> None:
    rb = load_rulebase("immune")
    assert compiled(rb) is compiled(load_rulebase("immune"))
    coarse = compile_rulebase(rb, cells=40, tol=1e-2)
    assert isinstance(coarse, CompiledSurface) and coarse.n[0] == 41
    with pytest.raises(InputError, match="cells >= 2"):
        compile_rulebase(rb, cells=1)


def test_lookup_helpers_agree() -> None:
    cs = compiled(load_rulebase("deffao"))
    out = np.empty(3)
    surface_lookup(cs.table, 0.4, -1.2, out)
    np.testing.assert_array_equal(out, cs.lookup(0.4, -1.2))
    assert surface_value(cs.table, 2, 0.4, -1.2) == out[2]
    assert np.isnan(surface_value(cs.table, 0, 0.1, np.nan))
