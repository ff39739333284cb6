"""FMI 2.0 source FMU: fmpy validate, a build from its sources, and an FMU2Slave loop over the
test vectors matching the C library bit for bit (sampling convention pinned)."""

from __future__ import annotations

import os
import shutil
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest
from helpers import LAWS, CLaw, case, needs_cc, write_c

from chassistune.controllers import laws
from chassistune.export import c99, fmu
from chassistune.export.write import files

fmpy = pytest.importorskip("fmpy", reason="fmpy (test extra) not installed")
from fmpy import read_model_description  # noqa: E402
from fmpy.build import build_platform_binary  # noqa: E402
from fmpy.fmi2 import FMU2Slave  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

pytestmark = needs_cc


@pytest.fixture(autouse=True)
def _cmake_on_path(monkeypatch: pytest.MonkeyPatch) -> None:
    """fmpy builds source FMUs with cmake (a pip wheel beside this interpreter)."""
    monkeypatch.setenv("PATH", f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    if shutil.which("cmake") is None:
        pytest.skip("cmake (needed by fmpy to build source FMUs) not installed")


def _built(controller: str, folder: Path) -> tuple[Path, Path]:
    """(the .fmu, its extracted folder with the platform binary built from sources/)."""
    ec = case(controller).ec
    path = folder / f"{ec.model_name}.fmu"
    path.write_bytes(files(ec, "fmu")[path.name])
    unzipped = folder / "unzipped"
    with zipfile.ZipFile(path) as zf:
        zf.extractall(unzipped)
    (folder / "build").mkdir()
    build_platform_binary(
        unzipped, folder / "build", cmake_options={"CMAKE_C_FLAGS:STRING": "-ffp-contract=off"}
    )
    return path, unzipped


def _slave(unzipped: Path) -> tuple[FMU2Slave, dict[str, int]]:
    md = read_model_description(unzipped)
    slave = FMU2Slave(
        guid=md.guid,
        unzipDirectory=str(unzipped),
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName="test",
    )
    slave.instantiate()
    return slave, {v.name: v.valueReference for v in md.modelVariables}


def _loop(
    slave: FMU2Slave, vr: dict[str, int], names: tuple[str, ...], inputs: np.ndarray, ts: float
) -> np.ndarray:
    """Set the inputs of row k, doStep(t_k, ts), read u: the k-th command."""
    ins = [vr[n] for n in names]
    out = np.empty(inputs.shape[0])
    for k, row in enumerate(inputs):
        slave.setReal(ins, row.tolist())
        slave.doStep(currentCommunicationPoint=k * ts, communicationStepSize=ts)
        out[k] = slave.getReal([vr["u"]])[0]
    return out


@pytest.mark.parametrize("controller", LAWS)
def test_fmu_validates_and_its_slave_matches_the_c_library_bit_for_bit(
    controller: str, tmp_path: Path
) -> None:
    c = case(controller)
    path, unzipped = _built(controller, tmp_path)
    assert validate_fmu(str(path)) == []
    md = read_model_description(str(path))
    assert md.fmiVersion == "2.0" and md.coSimulation is not None
    assert float(md.defaultExperiment.stepSize) == c.ec.ts_s
    with zipfile.ZipFile(path) as zf:
        names = set(zf.namelist())
    assert {
        "modelDescription.xml",
        "sources/controller.c",
        "sources/controller.h",
        "sources/fmu.c",
    } <= names
    assert not any(n.startswith("binaries/") for n in names)  # a source FMU
    assert not any("fmi2" in n for n in names)  # the FMI headers are the importer's
    slave, vr = _slave(unzipped)
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    assert slave.getReal([vr["u"]])[0] == 0.0  # before the first doStep
    got = _loop(slave, vr, c.ec.law.inputs, c.inputs, c.ec.ts_s)
    slave.terminate()
    slave.freeInstance()
    library = CLaw(write_c(c.ec, tmp_path / "c"), c99.BITWISE_FLAGS).run(c.inputs)
    assert np.array_equal(got, library)
    assert np.array_equal(got, c.u)


def test_gains_are_tunable_parameters_and_the_step_is_the_sample_time(tmp_path: Path) -> None:
    c = case("pid")
    _, unzipped = _built("pid", tmp_path)
    md = read_model_description(unzipped)
    kinds = {v.name: (v.causality, v.variability) for v in md.modelVariables}
    assert kinds["kp"] == ("parameter", "tunable")
    assert kinds["ts_s"] == ("parameter", "fixed")
    assert kinds["u"] == ("output", "discrete")
    slave, vr = _slave(unzipped)
    slave.setupExperiment(startTime=0.0)
    slave.enterInitializationMode()
    slave.setReal([vr["kp"], vr["kd"]], [1234.5, 77.0])
    slave.exitInitializationMode()
    got = _loop(slave, vr, c.ec.law.inputs, c.inputs[:200], c.ec.ts_s)
    params = c.ec.params.copy()
    params[c.ec.law.params.index("kp")] = 1234.5
    params[c.ec.law.params.index("kd")] = 77.0
    from chassistune.controllers import discrete

    expected = discrete.run_vectors(
        laws.kind(c.ec.law.controller), c.inputs[:200], params, c.ec.table, c.ec.grid
    )
    assert np.array_equal(got, expected)
    with pytest.raises(Exception, match="fmi2DoStep"):
        slave.doStep(currentCommunicationPoint=1.0, communicationStepSize=0.5 * c.ec.ts_s)
    slave.freeInstance()
    assert fmu.guid(c.ec) == md.guid  # the GUID is derived from the exported C
