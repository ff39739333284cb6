"""Benchmark functions F1-F23 (`get("F14")` returns a callable on `(n, d)` arrays)."""

from chassistune.benchmarks.functions import BenchmarkFunction, catalogue, get, names

__all__ = ["BenchmarkFunction", "catalogue", "get", "names"]
