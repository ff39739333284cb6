"""Shared fixtures of the fuzzy tests."""

from __future__ import annotations

import pytest

from chassistune.fuzzy import RuleBase, load_rulebase

BUILTINS = ("deffao", "classic", "immune")


@pytest.fixture(scope="session", params=BUILTINS)
def builtin(request: pytest.FixtureRequest) -> RuleBase:
    return load_rulebase(request.param)
