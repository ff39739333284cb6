"""Every output option is checked before any work: an existing file where a
folder goes (or as the folder of a file), a missing folder, a read-only folder and /proc each
give one line, exit 2, nothing written, and the work never starts."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from chassistune.errors import InputError

STUDY = """
[study]
name = "pre"
seeds = 1
[[scenarios]]
name = "qc"
plant = "quarter-car"
controller = "pid"
objective = "rms-ratio-exact"
[[optimizers]]
name = "pso"
[budget]
pop_size = 6
iterations = 2
"""


def _no_work(*args: object, **kwargs: object) -> None:
    raise AssertionError("the work started before the output was checked")


@pytest.fixture
def forbid_work(monkeypatch: pytest.MonkeyPatch) -> None:
    """Every entry point of real work raises: a test passing proves none was reached."""
    import chassistune.cli.study as study_cli  # noqa: F401 - the modules patched below
    import chassistune.reports.outputs
    import chassistune.reports.tables
    import chassistune.scenarios.abs_wheel
    import chassistune.studies.runner
    import chassistune.studies.store

    for cls in (chassistune.scenarios.abs_wheel.AbsWheelScenario,):
        monkeypatch.setattr(cls, "raw", _no_work)
        monkeypatch.setattr(cls, "trace", _no_work)
    monkeypatch.setattr(chassistune.reports.outputs, "write_demo", _no_work)
    import chassistune.export.source

    monkeypatch.setattr(chassistune.export.source, "resolve", _no_work)
    monkeypatch.setattr(chassistune.studies.runner, "run_study", _no_work)
    monkeypatch.setattr(chassistune.studies.store, "open_study", _no_work)
    import chassistune.plots.fuzzy

    monkeypatch.setattr(chassistune.plots.fuzzy, "plot_rulebase", _no_work)


def _read_only_folder(tmp_path: Path) -> Path:
    """A folder this process cannot write in: mode 0o555, or for root (whom modes do not stop)
    the read-only sysfs root."""
    if os.geteuid() != 0:
        folder = tmp_path / "ro"
        folder.mkdir()
        folder.chmod(0o555)
        return folder
    try:
        fd = os.open("/sys/.chassistune-probe", os.O_CREAT | os.O_WRONLY, 0o600)
    except OSError:
        return Path("/sys")
    os.close(fd)
    os.unlink("/sys/.chassistune-probe")
    pytest.skip("no read-only folder available to root here")


def _targets(tmp_path: Path, case: str, kind: str, name: str) -> str:
    afile = tmp_path / "afile"
    afile.write_text("x")
    if case == "existing-file":
        return str(afile) if kind == "dir" else str(afile / name)
    if case == "missing-folder":
        return str(tmp_path / "missing" / name)
    if case == "read-only":
        return str(_read_only_folder(tmp_path) / name)
    return f"/proc/{name}"


def _commands(tmp_path: Path, out: str) -> dict[str, list[str]]:
    config = tmp_path / "study.toml"
    config.write_text(STUDY)
    return {
        "simulate --plot": ["simulate", "abs-wheel", "--plot", out],
        "simulate --csv": ["simulate", "abs-wheel", "--csv", out],
        "tune --out": [
            "tune",
            "abs-wheel",
            "--controller",
            "pid",
            "--optimizer",
            "pso",
            "--pop",
            "4",
            "--iters",
            "1",
            "--out",
            out,
        ],
        "study run --out": ["study", "run", str(config), "--out", out],
        "study export --output": [
            "study",
            "export",
            str(tmp_path),
            "--format",
            "csv",
            "--output",
            out,
        ],
        "fuzzy show --plot": ["fuzzy", "show", "deffao", "--plot", out],
        "demo --out": ["demo", "--out", out],
        "export --out": ["export", "--controller", "pid", "--format", "json", "--out", out],
    }


OPTIONS = {
    "simulate --plot": ("file", "x.png"),
    "simulate --csv": ("file", "x.csv"),
    "tune --out": ("dir", "tuned"),
    "study run --out": ("dir", "st"),
    "study export --output": ("file", "x.csv"),
    "fuzzy show --plot": ("file", "x.png"),
    "demo --out": ("dir", "demo"),
    "export --out": ("dir", "ecu"),
}


def _snapshot(tmp_path: Path) -> set[str]:
    return {str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*")}


@pytest.mark.parametrize("case", ["existing-file", "missing-folder", "read-only", "proc"])
@pytest.mark.parametrize("option", list(OPTIONS))
def test_a_bad_output_is_refused_before_any_work(cli, tmp_path, forbid_work, option, case):
    if option == "export --out" and case == "missing-folder":
        pytest.skip("export creates missing folders by design (docs/export.md)")
    kind, name = OPTIONS[option]
    out = _targets(tmp_path, case, kind, name)
    args = _commands(tmp_path, out)[option]
    before = _snapshot(tmp_path)
    r = cli(*args)
    assert r.code == 2, (r.code, r.err)
    assert r.err.count("\n") == 1 and r.err.startswith("chassistune: error: "), r.err
    flag = option.split()[-1]
    assert flag in r.err, r.err
    assert r.out == ""
    assert _snapshot(tmp_path) == before
    assert not os.path.exists(out) or case == "existing-file"


def test_simulate_with_a_good_plot_and_a_bad_csv_writes_nothing(cli, tmp_path, forbid_work):
    png = tmp_path / "ok.png"
    r = cli("simulate", "abs-wheel", "--plot", str(png), "--csv", "/proc/x.csv")
    assert r.code == 2 and "--csv" in r.err
    assert not png.exists()


def test_an_oserror_during_the_write_is_one_line_and_exit_2(cli, tmp_path, monkeypatch):
    import chassistune.cli.simulate as sim_cli

    def full(result: object, path: str) -> None:
        raise OSError(28, "No space left on device", path)

    monkeypatch.setattr(sim_cli, "write_csv", full)
    r = cli("simulate", "abs-wheel", "--controller", "none", "--csv", str(tmp_path / "x.csv"))
    assert r.code == 2 and r.err.count("\n") == 1
    assert "No space left on device" in r.err


def test_the_checker_refuses_a_folder_named_as_a_file(tmp_path):
    from chassistune.cli.common import check_output_file

    with pytest.raises(InputError, match="is a folder"):
        check_output_file(str(tmp_path), "--csv")
