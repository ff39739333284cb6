"""`chassistune optimize`: JSON keys of design.md 7, determinism, one-line errors with exit 2."""

from __future__ import annotations

import json

import pytest

from chassistune.cli.main import main

KEYS = {
    "function",
    "dim",
    "optimizer",
    "best_f",
    "best_x",
    "nfev",
    "nit",
    "history",
    "history_nfev",
}


def _run(args: list[str], capsys: pytest.CaptureFixture[str]) -> tuple[int, str, str]:
    with pytest.raises(SystemExit) as exc:
        main(args)
    out, err = capsys.readouterr()
    return int(exc.value.code or 0), out, err


def test_json_output(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _err = _run(
        ["optimize", "F16", "--optimizer", "derlsp-ao", "--evals", "800", "--seed", "3", "--json"],
        capsys,
    )
    assert code == 0
    data = json.loads(out)
    assert set(data) == KEYS
    assert data["function"] == "F16" and data["dim"] == 2 and data["optimizer"] == "derlsp-ao"
    assert data["nfev"] == 800 and len(data["history"]) == data["nit"] == len(data["history_nfev"])
    assert data["best_f"] == data["history"][-1] and len(data["best_x"]) == 2
    code, again, _ = _run(
        ["optimize", "F16", "--optimizer", "derlsp-ao", "--evals", "800", "--seed", "3", "--json"],
        capsys,
    )
    assert again == out


def test_defaults_and_dim(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _run(["optimize", "f1", "--optimizer", "gwo", "--dim", "3", "--json"], capsys)
    data = json.loads(out)
    assert code == 0 and data["dim"] == 3 and data["nit"] == 100 and data["nfev"] == 30 * 101
    code, out, _ = _run(
        ["optimize", "F7", "--optimizer", "pso", "--iters", "2", "--pop", "5"], capsys
    )
    assert code == 0 and "pso on F7 (dim 30)" in out


@pytest.mark.parametrize(
    ("args", "field"),
    [
        (["optimize", "F99", "--optimizer", "ao"], "FUNCTION"),
        (["optimize", "F1", "--optimizer", "nope"], "--optimizer"),
        (["optimize", "F1", "--optimizer", "de", "--pop", "3"], "--pop"),
        (["optimize", "F16", "--optimizer", "ao", "--dim", "5"], "--dim"),
        (["optimize", "F1", "--optimizer", "ao", "--iters", "0"], "--iters"),
        (["optimize", "F1", "--optimizer", "ao", "--evals", "-5"], "--evals"),
        (["optimize", "F1", "--optimizer", "ao", "--iters", "5", "--evals", "9"], "--iters"),
        (["optimize", "F1", "--optimizer", "ao", "--seed", "-1"], "--seed"),
        (["optimize", "F1", "--optimizer", "ao", "--pop", "x"], "--pop"),
        (["optimize", "F1"], "--optimizer"),
    ],
)
def test_bad_input_exits_2_with_one_line(
    args: list[str], field: str, capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, err = _run(args, capsys)
    assert code == 2 and out == ""
    assert err.count("\n") == 1 and err.startswith("chassistune: error: ")
    assert field in err
