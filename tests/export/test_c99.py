"""C99 export: exact numbers in the header, bit-exact replay of the test vectors, the FMA build,
no library calls, and the closed loop with the C controller in it."""

from __future__ import annotations

import re
import subprocess
import zlib
from pathlib import Path

import numpy as np
import pytest
from helpers import CC, CONTINUOUS, LAWS, CLaw, case, gain_rows, needs_cc, write_c

from chassistune.export import c99, closed_loop, source, vectors
from chassistune.export.write import files

pytestmark = needs_cc


def _macro(text: str, name: str) -> str:
    """The body of a (possibly continued) #define."""
    m = re.search(rf"^#define {name} (.*?)(?<!\\)$", text, flags=re.M | re.S)
    assert m, name
    return m.group(1).replace("\\\n", " ")


def _numbers(body: str) -> np.ndarray:
    return np.array([float(t) for t in re.findall(r"[-+0-9.eE]+", body)])


@pytest.mark.parametrize("controller", LAWS)
def test_header_declares_inputs_and_prints_every_number_exactly(controller: str) -> None:
    ec = case(controller).ec
    text = c99.header(ec)
    names = re.findall(r'"(\w+)"', _macro(text, "CT_INPUT_NAMES"))
    assert tuple(names) == ec.law.inputs
    assert int(_macro(text, "CT_N_INPUTS")) == len(ec.law.inputs)
    for name, value in ec.param_dict().items():
        assert float(_macro(text, f"CT_P_{c99.c_name(name)}")) == value
    if ec.table_outputs:
        for k, out in enumerate(ec.table_outputs):
            assert np.array_equal(
                _numbers(_macro(text, f"CT_TABLE_{c99.c_name(out)}")), ec.table[k].ravel()
            )
        for name, bp in zip(ec.table_inputs, ec.breakpoints, strict=True):
            assert np.array_equal(_numbers(_macro(text, f"CT_BP_{c99.c_name(name)}")), bp)
        assert "(rows)" in text and "(columns)" in text
    assert "typedef struct" in text and "} ct_state;" in text


@pytest.mark.parametrize("controller", LAWS)
def test_bitwise_build_reproduces_the_test_vectors(controller: str, tmp_path: Path) -> None:
    c = case(controller)
    folder = write_c(c.ec, tmp_path)
    (folder / "test_vectors.csv").write_text(vectors.csv_text(c.ec.law.inputs, c.inputs, c.u))
    header, data = vectors.read_csv(str(folder / "test_vectors.csv"))
    assert header == (*c.ec.law.inputs, "u")
    assert np.array_equal(data[:, :-1], c.inputs) and np.array_equal(data[:, -1], c.u)
    assert data.shape[0] * c.ec.ts_s > 3.0  # a whole stop (about 3.5 s from 30 m/s)
    u = CLaw(folder, c99.BITWISE_FLAGS).run(data[:, :-1])
    assert np.array_equal(u, data[:, -1])


def _has_fma() -> bool:
    try:
        return " fma " in f" {Path('/proc/cpuinfo').read_text()} ".replace("\n", " ")
    except OSError:
        return False


@pytest.mark.skipif(not _has_fma(), reason="this CPU has no FMA instructions")
@pytest.mark.parametrize("controller", CONTINUOUS)
def test_fma_build_stays_within_1e9_relative(controller: str, tmp_path: Path) -> None:
    c = case(controller)
    folder = write_c(c.ec, tmp_path)
    flags = ("-std=c99", "-O2", "-ffp-contract=fast", "-mfma")
    asm = subprocess.run(
        [str(CC), *flags, "-S", "-o", "-", str(folder / c99.SOURCE)],
        check=True,
        capture_output=True,
        text=True,
    ).stdout
    assert "vfmadd" in asm or "vfmsub" in asm or "vfnmadd" in asm  # contraction did happen
    u = CLaw(folder, flags).run(c.inputs)
    scale = np.max(np.abs(c.u))
    np.testing.assert_allclose(u, c.u, rtol=1e-9, atol=1e-9 * scale)


@pytest.mark.parametrize("controller", LAWS)
def test_object_calls_no_library_function(controller: str, tmp_path: Path) -> None:
    folder = write_c(case(controller).ec, tmp_path)
    obj = folder / "controller.o"
    subprocess.run(
        [str(CC), *c99.BITWISE_FLAGS, "-c", "-o", str(obj), str(folder / c99.SOURCE)], check=True
    )
    undefined = subprocess.run(
        ["nm", "-u", str(obj)], check=True, capture_output=True, text=True
    ).stdout.split()
    assert undefined == []
    defined = subprocess.run(
        ["nm", "-g", "--defined-only", str(obj)], check=True, capture_output=True, text=True
    ).stdout
    assert sorted(line.split()[-1] for line in defined.splitlines()) == ["ct_init", "ct_step"]
    data = subprocess.run(["nm", str(obj)], check=True, capture_output=True, text=True).stdout
    assert not re.search(r" [BbDd] ", data)  # no mutable globals (tables are read-only)


@pytest.mark.parametrize("controller", LAWS)
def test_real_closed_loop_with_the_c_controller_gives_the_kernels_stop(
    controller: str, tmp_path: Path
) -> None:
    """Must show: the plant integrated as the kernel does (`closed_loop`, from the plant's public
    interface) with the compiled C called through ctypes at each control step gives the stop
    distance of the kernel that runs the discrete law (the realistic ECU kernel with the ideal
    ECU of the export) to 1e-12."""
    c = case(controller)
    law = CLaw(write_c(c.ec, tmp_path), c99.BITWISE_FLAGS)
    law.reset()
    with_c = closed_loop.run(c.ec.scenario, c.ec.ts_s, law, c.ec.law.inputs)
    kernel = c.ec.scenario.metrics(gain_rows(c.ec))
    assert with_c.status == 0 and kernel["status"][0] == "stopped"
    assert abs(with_c.stop_distance_m - kernel["stop_distance_m"][0]) <= 1e-12
    assert abs(with_c.stop_time_s - kernel["stop_time_s"][0]) <= 1e-12
    assert np.array_equal(with_c.u, c.u)  # the test vectors are this loop's commands
    assert np.array_equal(with_c.inputs(c.ec.law.inputs), c.inputs)


@pytest.mark.parametrize("controller", CONTINUOUS)
def test_closed_loop_check_sees_a_gain_one_part_in_a_billion_off(
    controller: str, tmp_path: Path
) -> None:
    """The 1e-12 check can fail: a C controller whose first gain is 1e-9 (relative) off moves
    the stop by more than 1e-11 m."""
    ec = case(controller).ec
    name, value = next(iter(ec.gains.items()))
    off = source.resolve(None, None, controller, {name: value * (1.0 + 1e-9)}, {})
    law = CLaw(write_c(off, tmp_path), c99.BITWISE_FLAGS)
    law.reset()
    run = closed_loop.run(ec.scenario, ec.ts_s, law, ec.law.inputs)
    kernel = ec.scenario.metrics(gain_rows(ec))["stop_distance_m"][0]
    assert abs(run.stop_distance_m - kernel) > 1e-11


def test_shipped_check_program_replays_the_vectors_and_catches_a_change(tmp_path: Path) -> None:
    for name, data in files(case("fuzzy-immune-pid").ec, "c").items():
        (tmp_path / name).write_bytes(data)
    exe = tmp_path / "ct_check"
    subprocess.run(
        [
            str(CC),
            *c99.BITWISE_FLAGS,
            "-o",
            str(exe),
            str(tmp_path / c99.SOURCE),
            str(tmp_path / c99.CHECK),
        ],
        check=True,
    )
    ok = subprocess.run([str(exe)], cwd=tmp_path, capture_output=True, text=True, check=False)
    assert ok.returncode == 0 and " 0 mismatches" in ok.stdout
    lines = (tmp_path / "test_vectors.csv").read_text().splitlines()
    last = lines[-1].split(",")
    last[-1] = repr(np.nextafter(float(last[-1]), np.inf))  # one ulp off
    (tmp_path / "bad.csv").write_text("\n".join([*lines[:-1], ",".join(last)]) + "\n")
    bad = subprocess.run(
        [str(exe), "bad.csv"], cwd=tmp_path, capture_output=True, text=True, check=False
    )
    assert bad.returncode == 1 and " 1 mismatches" in bad.stdout


@pytest.mark.parametrize(
    ("controller", "road", "params"),
    [
        ("fuzzy-pid", "ice", {"rulebase": "classic", "fuzzy_table_points": 33}),
        ("fuzzy-immune-pid", "dirt-0.2", {"ts_s": 0.002}),
        ("pid", "wet-asphalt", {"ecu_ts_s": 0.01, "dt_s": 5e-4}),
        ("threshold", "ice", {"ts_s": 0.005}),
        ("mpc", "ice", {"horizon": 3}),
    ],
)
def test_bitwise_on_other_roads_presets_rule_bases_and_random_gains(
    controller: str, road: str, params: dict[str, object], tmp_path: Path
) -> None:
    preset = "paper-fuzzy-immune" if road == "dirt-0.2" else None
    ec = source.resolve(None, None, controller, {}, params, preset, road)
    rng = np.random.default_rng(zlib.crc32(controller.encode()))
    spec = ec.scenario.controller
    gains = {g.name: str(rng.uniform(g.lo, g.hi)) for g in spec.gains}
    for chosen in ({}, gains):
        ec = source.resolve(None, None, controller, chosen, params, preset, road)
        inputs, u = vectors.record(ec)
        folder = write_c(ec, tmp_path / str(len(chosen)))
        assert np.array_equal(CLaw(folder, c99.BITWISE_FLAGS).run(inputs), u)


@pytest.mark.parametrize("controller", LAWS)
def test_bitwise_on_arbitrary_inputs_nan_and_infinities(controller: str, tmp_path: Path) -> None:
    """Any input sequence, not only recorded ones: out-of-range slip, exact grid nodes, the
    clipping edges, NaN and infinities (which then stay in the state of both)."""
    ec = case(controller).ec
    rng = np.random.default_rng(zlib.crc32(b"fuzz" + controller.encode()))
    m = 4000
    cols = []
    for name in ec.law.inputs:
        if name == "slip":
            col = rng.uniform(-0.5, 1.5, m)
            col[::7] = np.round(col[::7], 2)  # many exact steps of the grid once scaled
        elif name == "wheel_speed_rad_s":
            col = np.cumsum(rng.normal(0.0, 0.5, m)) + 60.0
        else:
            col = (rng.uniform(size=m) < 0.3).astype(float)
        cols.append(col)
    finite = np.column_stack(cols)
    special = finite[:200].copy()
    special[50:, 0] = [np.inf, -np.inf, np.nan, 0.0, -0.0, 1.0] * 25
    lib = CLaw(write_c(ec, tmp_path), c99.BITWISE_FLAGS)
    for rows in (finite, special):
        expected = vectors.replay(ec, rows)
        assert np.array_equal(lib.run(rows), expected, equal_nan=True)
