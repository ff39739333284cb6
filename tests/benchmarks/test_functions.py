"""F1-F23: known minima at known minimizers, vectorization, and opfunu cross-checks (F15-F20)."""

from __future__ import annotations

import numpy as np
import pytest

from chassistune import benchmarks
from chassistune.benchmarks.functions import REGISTRY
from chassistune.errors import InputError

DETERMINISTIC = [n for n in benchmarks.names() if n != "F7"]


def test_catalogue_lists_the_23_functions() -> None:
    cat = benchmarks.catalogue()
    assert [c["name"] for c in cat] == [f"F{i}" for i in range(1, 24)]
    for c in cat:
        assert {"name", "description", "dim", "bounds", "f_min"} <= set(c)
        assert len(c["bounds"]) == c["dim"]


@pytest.mark.parametrize("name", DETERMINISTIC)
def test_known_minimum_at_known_minimizer(name: str) -> None:
    fn = benchmarks.get(name)
    dims = [fn.dim] if not fn.scalable else [fn.dim, 2, 7]
    for d in dims:
        x = fn.minimizer(d)
        b = fn.bounds(d)
        assert np.all((b[:, 0] <= x) & (x <= b[:, 1]))
        tol = 2e-4 if name in ("F21", "F22", "F23") else 1e-9 * max(1.0, abs(fn.f_min(d)))
        assert abs(fn(x) - fn.f_min(d)) <= tol


@pytest.mark.parametrize(
    ("name", "quoted"), [("F21", -10.1532), ("F22", -10.4028), ("F23", -10.5363)]
)
def test_shekel_quoted_values_within_tolerance(name: str, quoted: float) -> None:
    fn = benchmarks.get(name)
    assert abs(fn(np.full(4, 4.0)) - quoted) < 2e-4
    assert abs(fn.f_min() - quoted) < 2e-4


@pytest.mark.parametrize("name", ["F21", "F22", "F23"])
def test_shekel_depends_on_every_coordinate(name: str) -> None:
    fn = benchmarks.get(name)  # a published port's Shekel reads x1 only
    x = np.full((4, 4), 4.0)
    x[np.arange(4), np.arange(4)] = 5.0
    assert np.all(fn(x) > fn.f_min() + 1.0)


def test_known_minima_values() -> None:
    expected = {
        "F8": -418.982887 * 30,
        "F14": 0.998003838,
        "F15": 3.0748598e-4,
        "F16": -1.0316284535,
        "F17": 0.397887358,
        "F18": 3.0,
        "F19": -3.86278214782,
        "F20": -3.32236801142,
        "F21": -10.1531997,
        "F22": -10.4029406,
        "F23": -10.5364098,
    }
    for name, value in expected.items():
        assert benchmarks.get(name).f_min() == pytest.approx(value, rel=1e-8, abs=1e-9)


@pytest.mark.parametrize("name", DETERMINISTIC)
def test_batch_rows_equal_single_points(name: str) -> None:
    fn = benchmarks.get(name)
    rng = np.random.default_rng(1)
    b = fn.bounds()
    x = b[:, 0] + rng.random((9, b.shape[0])) * (b[:, 1] - b[:, 0])
    batch = fn(x)
    assert batch.shape == (9,)
    single = np.array([fn(row) for row in x])
    np.testing.assert_allclose(batch, single, rtol=1e-13, atol=0)


def test_f6_is_yaos_step_and_f7_takes_a_generator() -> None:
    assert benchmarks.get("F6")(np.array([[0.49, -0.5, 1.5]])) == pytest.approx(0.0 + 0.0 + 4.0)
    f7 = benchmarks.get("F7")
    noise = f7(np.zeros((1000, 30)), np.random.default_rng(0))
    assert np.all((noise >= 0) & (noise < 1))
    with pytest.raises(InputError, match="Generator"):
        f7(np.zeros((2, 30)))


def test_bad_names_and_dimensions_raise_value_errors() -> None:
    with pytest.raises(ValueError, match="unknown function"):
        benchmarks.get("F24")
    with pytest.raises(ValueError, match="dim = 2 only"):
        benchmarks.get("F16")(np.zeros((3, 5)))
    with pytest.raises(ValueError, match="dim >= 2"):
        benchmarks.get("F5").bounds(1)
    assert benchmarks.get("f1") is REGISTRY.get("F1")


OPFUNU = {
    "F15": "Kowalik",
    "F16": "CamelSixHump",
    "F17": "Branin01",
    "F18": "GoldsteinPrice",
    "F19": "Hartmann3",
    "F20": "Hartmann6",
}


@pytest.mark.parametrize("name", sorted(OPFUNU))
def test_agrees_with_opfunu(name: str) -> None:
    nb = pytest.importorskip("opfunu.name_based")
    ref = getattr(nb, OPFUNU[name])()
    fn = benchmarks.get(name)
    b = fn.bounds()
    rng = np.random.default_rng(7)
    x = b[:, 0] + rng.random((200, b.shape[0])) * (b[:, 1] - b[:, 0])
    expected = np.array([ref.evaluate(row) for row in x])
    np.testing.assert_allclose(fn(x), expected, rtol=1e-12, atol=1e-12)
