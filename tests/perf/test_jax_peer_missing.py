"""Without JAX the bench notes the peer figures as not measured, with the reason, and measures
nothing else in their place."""

from __future__ import annotations

import importlib.util
import json
import sys
from typing import Any

import pytest
from click.testing import CliRunner

from chassistune.cli.bench import bench_command


def test_bench_notes_the_jax_figures_missing_without_jax(monkeypatch: pytest.MonkeyPatch) -> None:
    real = importlib.util.find_spec

    def find_spec(name: str, *args: Any) -> Any:
        return None if name == "jax" else real(name, *args)

    monkeypatch.setattr(importlib.util, "find_spec", find_spec)
    monkeypatch.delitem(sys.modules, "chassistune.perf.jax_peer", raising=False)
    result = CliRunner().invoke(bench_command, ["--only", "jax_peer", "--json"])
    assert result.exit_code == 0, result.output
    out = json.loads(result.output)
    assert set(out) == {"notes"}
    assert "abs_speedup_vs_jax not measured: jax is not installed" in out["notes"]["jax_peer"]
