"""Peak memory of a 100-run study (run, report, export) stays under 500 MB.

Measured as the study process's VmHWM: Linux carries ru_maxrss across fork and exec, so a child
of a big pytest process would report its parent's size.
"""

from __future__ import annotations

import subprocess
import sys

from studies_helpers import tiny_config, write_plan

LIMIT_MB = 500

SCRIPT = """
import sys
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
hwm = [line for line in open("/proc/self/status") if line.startswith("VmHWM:")][0]
print(outcome.completed, int(hwm.split()[1]))
"""


def test_a_100_run_study_peaks_under_500_mb(tmp_path):
    config, plan = write_plan(tmp_path, tiny_config(seeds=25, roads='["iso-b", "iso-c"]'))
    assert len(plan.runs) == 100
    done = subprocess.run(
        [sys.executable, "-c", SCRIPT, str(config), str(tmp_path / "out")],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert done.returncode == 0, done.stderr
    completed, maxrss_kb = map(int, done.stdout.split()[-2:])
    peak_mb = maxrss_kb / 1024  # VmHWM is in kB
    print(f"\npeak memory of the 100-run study (run, report, export): {peak_mb:.0f} MB")
    assert completed == 100
    assert peak_mb < LIMIT_MB
