"""The classic test functions F1-F23 (Yao, Liu and Lin 1999), vectorized over `(n, d)` arrays.

Each function is data (`BenchmarkFunction`: bounds, usual dimension, known minimum and minimizer)
plus a vectorized formula. `get(name)(x)` maps an `(n, d)` array to `(n,)` costs; a 1-D `x` is one
point and gives a float. F7 adds uniform noise in [0, 1) and needs a Generator: `get("F7")(x, rng)`.

Choices (optimizers_design.md): F6 is Yao's step, sum floor(x + 0.5)^2 (some codes drop the floor);
F20 uses p(3, 2) = 0.1451 (minimum -3.32236801142; the common MATLAB code's 0.1415 gives
-3.32199517); F21-F23 are Shekel 5/7/10 over all four coordinates, with minima -10.1531997,
-10.4029406, -10.5364098 at points near (4, 4, 4, 4) (the often quoted -10.1532 / -10.4028 /
-10.5363 are the values at (4, 4, 4, 4) itself). The minimizers of F14, F15, F19-F23 below were
polished with BFGS from the published points.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from chassistune._registry import Registry
from chassistune.errors import InputError

FloatArray = NDArray[np.float64]

SCHWEFEL_X = 420.968745461094
SCHWEFEL_F = -418.9828872724337

# --- formulas (x has shape (n, d); each returns shape (n,)) ---------------------------------------


def _sphere(x: FloatArray) -> FloatArray:
    return np.sum(x * x, axis=1)


def _schwefel_222(x: FloatArray) -> FloatArray:
    a = np.abs(x)
    return np.sum(a, axis=1) + np.prod(a, axis=1)


def _schwefel_12(x: FloatArray) -> FloatArray:
    return np.sum(np.cumsum(x, axis=1) ** 2, axis=1)


def _schwefel_221(x: FloatArray) -> FloatArray:
    return np.max(np.abs(x), axis=1)


def _rosenbrock(x: FloatArray) -> FloatArray:
    head, tail = x[:, :-1], x[:, 1:]
    return np.sum(100.0 * (tail - head * head) ** 2 + (head - 1.0) ** 2, axis=1)


def _step(x: FloatArray) -> FloatArray:
    return np.sum(np.floor(x + 0.5) ** 2, axis=1)


def _quartic(x: FloatArray) -> FloatArray:
    i = np.arange(1, x.shape[1] + 1)
    return np.sum(i * x**4, axis=1)


def _schwefel_226(x: FloatArray) -> FloatArray:
    return np.sum(-x * np.sin(np.sqrt(np.abs(x))), axis=1)


def _rastrigin(x: FloatArray) -> FloatArray:
    return np.sum(x * x - 10.0 * np.cos(2.0 * np.pi * x) + 10.0, axis=1)


def _ackley(x: FloatArray) -> FloatArray:
    d = x.shape[1]
    a = -20.0 * np.exp(-0.2 * np.sqrt(np.sum(x * x, axis=1) / d))
    return a - np.exp(np.sum(np.cos(2.0 * np.pi * x), axis=1) / d) + 20.0 + np.e


def _griewank(x: FloatArray) -> FloatArray:
    i = np.sqrt(np.arange(1, x.shape[1] + 1))
    return np.sum(x * x, axis=1) / 4000.0 - np.prod(np.cos(x / i), axis=1) + 1.0


def _u(x: FloatArray, a: float, k: float, m: float) -> FloatArray:
    return np.where(x > a, k * (x - a) ** m, np.where(x < -a, k * (-x - a) ** m, 0.0))


def _penalized_1(x: FloatArray) -> FloatArray:
    d = x.shape[1]
    y = 1.0 + (x + 1.0) / 4.0
    s = 10.0 * np.sin(np.pi * y[:, 0]) ** 2
    s = s + np.sum((y[:, :-1] - 1.0) ** 2 * (1.0 + 10.0 * np.sin(np.pi * y[:, 1:]) ** 2), axis=1)
    s = s + (y[:, -1] - 1.0) ** 2
    return np.pi / d * s + np.sum(_u(x, 10.0, 100.0, 4.0), axis=1)


def _penalized_2(x: FloatArray) -> FloatArray:
    s = np.sin(3.0 * np.pi * x[:, 0]) ** 2
    s = s + np.sum((x[:, :-1] - 1.0) ** 2 * (1.0 + np.sin(3.0 * np.pi * x[:, 1:]) ** 2), axis=1)
    s = s + (x[:, -1] - 1.0) ** 2 * (1.0 + np.sin(2.0 * np.pi * x[:, -1]) ** 2)
    return 0.1 * s + np.sum(_u(x, 5.0, 100.0, 4.0), axis=1)


_FOX = np.array(
    [
        [-32.0, -16.0, 0.0, 16.0, 32.0] * 5,
        [v for v in (-32.0, -16.0, 0.0, 16.0, 32.0) for _ in range(5)],
    ]
)


def _foxholes(x: FloatArray) -> FloatArray:
    diff6 = np.sum((x[:, :, None] - _FOX[None, :, :]) ** 6, axis=1)  # (n, 25)
    return 1.0 / (1.0 / 500.0 + np.sum(1.0 / (np.arange(1.0, 26.0) + diff6), axis=1))


_KOW_A = np.array(
    [0.1957, 0.1947, 0.1735, 0.16, 0.0844, 0.0627, 0.0456, 0.0342, 0.0323, 0.0235, 0.0246]
)
_KOW_B = 1.0 / np.array([0.25, 0.5, 1.0, 2.0, 4.0, 6.0, 8.0, 10.0, 12.0, 14.0, 16.0])


def _kowalik(x: FloatArray) -> FloatArray:
    b = _KOW_B[None, :]
    x1, x2, x3, x4 = (x[:, j : j + 1] for j in range(4))
    model = x1 * (b * b + b * x2) / (b * b + b * x3 + x4)
    return np.sum((_KOW_A[None, :] - model) ** 2, axis=1)


def _six_hump_camel(x: FloatArray) -> FloatArray:
    a, b = x[:, 0], x[:, 1]
    return 4.0 * a * a - 2.1 * a**4 + a**6 / 3.0 + a * b - 4.0 * b * b + 4.0 * b**4


def _branin(x: FloatArray) -> FloatArray:
    a, b = x[:, 0], x[:, 1]
    q = b - 5.1 / (4.0 * np.pi**2) * a * a + 5.0 / np.pi * a - 6.0
    return q * q + 10.0 * (1.0 - 1.0 / (8.0 * np.pi)) * np.cos(a) + 10.0


def _goldstein_price(x: FloatArray) -> FloatArray:
    a, b = x[:, 0], x[:, 1]
    p = 1.0 + (a + b + 1.0) ** 2 * (
        19.0 - 14.0 * a + 3.0 * a * a - 14.0 * b + 6.0 * a * b + 3.0 * b * b
    )
    q = 30.0 + (2.0 * a - 3.0 * b) ** 2 * (
        18.0 - 32.0 * a + 12.0 * a * a + 48.0 * b - 36.0 * a * b + 27.0 * b * b
    )
    return p * q


_HART_C = np.array([1.0, 1.2, 3.0, 3.2])
_HART3_A = np.array([[3.0, 10.0, 30.0], [0.1, 10.0, 35.0], [3.0, 10.0, 30.0], [0.1, 10.0, 35.0]])
_HART3_P = np.array(
    [
        [0.3689, 0.117, 0.2673],
        [0.4699, 0.4387, 0.747],
        [0.1091, 0.8732, 0.5547],
        [0.03815, 0.5743, 0.8828],
    ]
)
_HART6_A = np.array(
    [
        [10.0, 3.0, 17.0, 3.5, 1.7, 8.0],
        [0.05, 10.0, 17.0, 0.1, 8.0, 14.0],
        [3.0, 3.5, 1.7, 10.0, 17.0, 8.0],
        [17.0, 8.0, 0.05, 10.0, 0.1, 14.0],
    ]
)
_HART6_P = np.array(
    [
        [0.1312, 0.1696, 0.5569, 0.0124, 0.8283, 0.5886],
        [0.2329, 0.4135, 0.8307, 0.3736, 0.1004, 0.9991],
        [0.2348, 0.1451, 0.3522, 0.2883, 0.3047, 0.6650],
        [0.4047, 0.8828, 0.8732, 0.5743, 0.1091, 0.0381],
    ]
)


def _hartman(a: FloatArray, p: FloatArray) -> Callable[[FloatArray], FloatArray]:
    def f(x: FloatArray) -> FloatArray:
        inner = np.sum(a[None] * (x[:, None, :] - p[None]) ** 2, axis=2)  # (n, 4)
        return -np.sum(_HART_C * np.exp(-inner), axis=1)

    return f


_SHEKEL_A = np.array(
    [
        [4.0, 4.0, 4.0, 4.0],
        [1.0, 1.0, 1.0, 1.0],
        [8.0, 8.0, 8.0, 8.0],
        [6.0, 6.0, 6.0, 6.0],
        [3.0, 7.0, 3.0, 7.0],
        [2.0, 9.0, 2.0, 9.0],
        [5.0, 5.0, 3.0, 3.0],
        [8.0, 1.0, 8.0, 1.0],
        [6.0, 2.0, 6.0, 2.0],
        [7.0, 3.6, 7.0, 3.6],
    ]
)
_SHEKEL_C = np.array([0.1, 0.2, 0.2, 0.4, 0.4, 0.6, 0.3, 0.7, 0.5, 0.5])


def _shekel(m: int) -> Callable[[FloatArray], FloatArray]:
    a, c = _SHEKEL_A[:m], _SHEKEL_C[:m]

    def f(x: FloatArray) -> FloatArray:
        sq = np.sum((x[:, None, :] - a[None]) ** 2, axis=2)  # (n, m): all four coordinates
        return -np.sum(1.0 / (sq + c), axis=1)

    return f


# --- the catalogue --------------------------------------------------------------------------------


@dataclass(frozen=True)
class BenchmarkFunction:
    """A test function with its data. Scalable functions (F1-F13) take any `dim >= min_dim`."""

    name: str
    description: str
    formula: Callable[[FloatArray], FloatArray]
    dim: int  # usual dimension
    lo: tuple[float, ...]  # one value (scalable: every coordinate) or one per coordinate
    hi: tuple[float, ...]
    x_min: tuple[float, ...]  # one value (scalable) or one per coordinate
    f_min_value: float  # scalable F8: per coordinate
    scalable: bool = False
    min_dim: int = 1
    noisy: bool = False

    def check_dim(self, dim: int | None) -> int:
        """The dimension to use (`dim` or the usual one); InputError if not defined there."""
        if dim is None:
            return self.dim
        if isinstance(dim, bool) or not isinstance(dim, int | np.integer):
            raise InputError("dim", f"expected an integer, got {dim!r}")
        if self.scalable and dim < self.min_dim:
            raise InputError("dim", f"{self.name} needs dim >= {self.min_dim}, got {dim}")
        if not self.scalable and dim != self.dim:
            raise InputError("dim", f"{self.name} is defined for dim = {self.dim} only, got {dim}")
        return int(dim)

    def bounds(self, dim: int | None = None) -> FloatArray:
        """Search bounds, shape `(dim, 2)`."""
        d = self.check_dim(dim)
        lo = np.broadcast_to(np.asarray(self.lo, dtype=float), (d,))
        hi = np.broadcast_to(np.asarray(self.hi, dtype=float), (d,))
        return np.stack([lo, hi], axis=1)

    def minimizer(self, dim: int | None = None) -> FloatArray:
        """A global minimizer, shape `(dim,)`."""
        d = self.check_dim(dim)
        return np.broadcast_to(np.asarray(self.x_min, dtype=float), (d,)).copy()

    def f_min(self, dim: int | None = None) -> float:
        """The known minimum (noise-free for F7)."""
        d = self.check_dim(dim)
        return self.f_min_value * d if self.name == "F8" else self.f_min_value

    def __call__(self, x: ArrayLike, rng: np.random.Generator | None = None) -> FloatArray:
        xa = np.asarray(x, dtype=float)
        if xa.ndim == 1:
            return self(xa[None, :], rng)[0]
        if xa.ndim != 2:
            raise InputError("x", f"expected an (n, d) array, got shape {xa.shape}")
        self.check_dim(xa.shape[1])
        out = self.formula(xa)
        if self.noisy:
            if not isinstance(rng, np.random.Generator):
                raise InputError("rng", f"{self.name} is noisy: pass a numpy.random.Generator")
            out = out + rng.random(xa.shape[0])
        return out

    def as_dict(self) -> dict[str, object]:
        """JSON-ready description (bounds and minimum at the usual dimension)."""
        return {
            "name": self.name,
            "description": self.description,
            "dim": self.dim,
            "scalable": self.scalable,
            "bounds": self.bounds().tolist(),
            "f_min": self.f_min(),
            "x_min": self.minimizer().tolist(),
            "noisy": self.noisy,
        }


def _fn(
    name: str,
    description: str,
    formula: Callable[[FloatArray], FloatArray],
    lo: float,
    hi: float,
    x_min: float = 0.0,
    f_min: float = 0.0,
    min_dim: int = 1,
    noisy: bool = False,
) -> BenchmarkFunction:
    return BenchmarkFunction(
        name,
        description,
        formula,
        30,
        (lo,),
        (hi,),
        (x_min,),
        f_min,
        scalable=True,
        min_dim=min_dim,
        noisy=noisy,
    )


REGISTRY: Registry[BenchmarkFunction] = Registry("function", key=str.upper)
for _f in [
    _fn("F1", "sphere", _sphere, -100.0, 100.0),
    _fn("F2", "Schwefel 2.22", _schwefel_222, -10.0, 10.0),
    _fn("F3", "Schwefel 1.2", _schwefel_12, -100.0, 100.0),
    _fn("F4", "Schwefel 2.21", _schwefel_221, -100.0, 100.0),
    _fn("F5", "Rosenbrock", _rosenbrock, -30.0, 30.0, x_min=1.0, min_dim=2),
    _fn("F6", "step, floor(x + 0.5)^2 (Yao)", _step, -100.0, 100.0),
    _fn(
        "F7",
        "quartic with uniform noise (needs a Generator)",
        _quartic,
        -1.28,
        1.28,
        noisy=True,
    ),
    _fn("F8", "Schwefel 2.26", _schwefel_226, -500.0, 500.0, x_min=SCHWEFEL_X, f_min=SCHWEFEL_F),
    _fn("F9", "Rastrigin", _rastrigin, -5.12, 5.12),
    _fn("F10", "Ackley", _ackley, -32.0, 32.0),
    _fn("F11", "Griewank", _griewank, -600.0, 600.0),
    _fn("F12", "penalized 1", _penalized_1, -50.0, 50.0, x_min=-1.0),
    _fn("F13", "penalized 2", _penalized_2, -50.0, 50.0, x_min=1.0),
    BenchmarkFunction(
        "F14",
        "Shekel's foxholes",
        _foxholes,
        2,
        (-65.536,),
        (65.536,),
        (-31.9783299932, -31.97833),
        0.9980038377944505,
    ),
    BenchmarkFunction(
        "F15",
        "Kowalik",
        _kowalik,
        4,
        (-5.0,),
        (5.0,),
        (0.19283345, 0.19083624, 0.1231173, 0.13576599),
        3.0748598780560557e-4,
    ),
    BenchmarkFunction(
        "F16",
        "six-hump camel back",
        _six_hump_camel,
        2,
        (-5.0,),
        (5.0,),
        (0.089842006, -0.712656409),
        -1.031628453489877,
    ),
    BenchmarkFunction(
        "F17",
        "Branin",
        _branin,
        2,
        (-5.0, 0.0),
        (10.0, 15.0),
        (np.pi, 2.275),
        0.39788735772973816,
    ),
    BenchmarkFunction(
        "F18", "Goldstein-Price", _goldstein_price, 2, (-2.0,), (2.0,), (0.0, -1.0), 3.0
    ),
    BenchmarkFunction(
        "F19",
        "Hartman 3",
        _hartman(_HART3_A, _HART3_P),
        3,
        (0.0,),
        (1.0,),
        (0.1146143636, 0.555648844, 0.8525469459),
        -3.8627821478207482,
    ),
    BenchmarkFunction(
        "F20",
        "Hartman 6 (p32 = 0.1451)",
        _hartman(_HART6_A, _HART6_P),
        6,
        (0.0,),
        (1.0,),
        (0.2016895136, 0.1500106893, 0.4768739738, 0.2753324271, 0.3116516158, 0.6573005364),
        -3.3223680114155143,
    ),
    BenchmarkFunction(
        "F21",
        "Shekel 5",
        _shekel(5),
        4,
        (0.0,),
        (10.0,),
        (4.0000371463, 4.0001332689, 4.0000371463, 4.0001332689),
        -10.153199679058208,
    ),
    BenchmarkFunction(
        "F22",
        "Shekel 7",
        _shekel(7),
        4,
        (0.0,),
        (10.0,),
        (4.0005729079, 4.0006893581, 3.9994897013, 3.9996061508),
        -10.402940566818637,
    ),
    BenchmarkFunction(
        "F23",
        "Shekel 10",
        _shekel(10),
        4,
        (0.0,),
        (10.0,),
        (4.0007465244, 4.0005929267, 3.9996633911, 3.9995097936),
        -10.536409816692023,
    ),
]:
    REGISTRY.register(_f.name, _f)


def names() -> list[str]:
    """F1 .. F23."""
    return REGISTRY.names()


def get(name: str) -> BenchmarkFunction:
    """The function `name` (case-insensitive, e.g. "F14" or "f14"); InputError if unknown."""
    return REGISTRY.get(name)


def catalogue() -> list[dict[str, object]]:
    """One dict per function: name, description, dim, bounds, f_min (and more)."""
    return [get(n).as_dict() for n in names()]
