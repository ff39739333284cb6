"""The one registry shape: duplicates refused, lazy entries imported on first use."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

from chassistune._registry import Registry, resolve
from chassistune.errors import InputError


def test_register_get_names_in_order() -> None:
    reg: Registry[int] = Registry("number")
    reg.register("two", 2)
    reg.register("one", 1)
    assert reg.names() == ["two", "one"]
    assert reg.get("one") == 1
    assert "two" in reg and "three" not in reg


def test_duplicate_is_refused() -> None:
    reg: Registry[int] = Registry("number")
    reg.register("one", 1)
    with pytest.raises(ValueError, match="registered already"):
        reg.register("one", 11)
    assert reg.get("one") == 1


def test_unknown_name_is_input_error_listing_known_names() -> None:
    reg: Registry[int] = Registry("number", field="params.n")
    reg.register("one", 1)
    reg.register("two", 2)
    with pytest.raises(InputError) as err:
        reg.get("three", " for this test")
    assert err.value.field == "params.n"
    assert err.value.problem == "unknown number 'three' for this test (known: one, two)"


def test_lazy_entry_is_imported_on_first_get_only(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    (tmp_path / "lazy_entry_module.py").write_text("VALUE = 42\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    reg: Registry[int] = Registry("thing")
    reg.register("answer", "lazy_entry_module:VALUE")
    assert reg.names() == ["answer"]
    assert "lazy_entry_module" not in sys.modules
    assert reg.get("answer") == 42
    assert "lazy_entry_module" in sys.modules
    monkeypatch.delitem(sys.modules, "lazy_entry_module")


def test_key_normalizes_lookups() -> None:
    reg: Registry[int] = Registry("function", key=str.upper)
    reg.register("F1", 1)
    assert reg.get("f1") == 1 and "f1" in reg


def test_resolve_refuses_a_path_without_attr() -> None:
    with pytest.raises(ValueError, match="module:attr"):
        resolve("fractions")
