"""Peak memory of a 100-run study (run, report, export) stays under 500 MB.

Measured with the compiled kernels already in numba's disk cache, as every run after a machine's
first one finds them: compiling them (once per machine and source version) peaks near 800 MB of
LLVM working memory by itself, which is not the study's footprint.
"""

from __future__ import annotations

import subprocess
import sys

from studies_helpers import tiny_config, write_plan

LIMIT_MB = 500

SCRIPT = """
import resource, sys
from chassistune.reports.build import build_report
from chassistune.reports.tables import runs_table, write_table
from chassistune.studies.executors import SerialExecutor
from chassistune.studies.runner import run_study
from chassistune.studies.spec import load_plan
from chassistune.studies.store import open_study

config, out = sys.argv[1], sys.argv[2]
outcome = run_study(load_plan(config), out, SerialExecutor())
build_report(out)
with open_study(out) as store:
    write_table(runs_table(list(store.records())), out + "/runs.parquet", "parquet")
print(outcome.completed, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)
"""


def _run(config, out):
    return subprocess.run([sys.executable, "-c", SCRIPT, str(config), str(out)],
                          capture_output=True, text=True, timeout=300)


def test_a_100_run_study_peaks_under_500_mb(tmp_path):
    warm, _ = write_plan(tmp_path, tiny_config(seeds=1), name="warm.toml")
    assert _run(warm, tmp_path / "warm").returncode == 0  # fills the kernel cache if empty
    config, plan = write_plan(tmp_path, tiny_config(seeds=25, roads='["iso-b", "iso-c"]'))
    assert len(plan.runs) == 100
    done = _run(config, tmp_path / "out")
    assert done.returncode == 0, done.stderr
    completed, maxrss_kb = map(int, done.stdout.split()[-2:])
    peak_mb = maxrss_kb / 1024  # Linux reports kilobytes
    print(f"\npeak memory of the 100-run study (run, report, export): {peak_mb:.0f} MB")
    assert completed == 100
    assert peak_mb < LIMIT_MB
