"""`chassistune warmup`: compile every kernel variant a command can reach now (cached on disk)
instead of at first use, and say what it compiled and how long it took."""

from __future__ import annotations

import os
import time

import click


def _warm_rest() -> None:
    """The kernels no scenario run reaches: the C export's closed-loop replay of each exportable
    law, the fuzzy engine of each built-in rule base (`fuzzy eval`) and the Magic Formula's
    peak and relaxation lengths of `chassistune tire` (on each shipped tyre file, with its
    lateral coefficients where it has them)."""
    from importlib.resources import files

    import numpy as np

    from chassistune.controllers import laws
    from chassistune.export import vectors
    from chassistune.export.source import exportable_plants, resolve
    from chassistune.fuzzy.engine import evaluate
    from chassistune.fuzzy.loader import builtin_names, load_rulebase

    for plant in exportable_plants():
        for law in (s.name for s in laws.for_plant(plant) if laws.get(s.name).discrete):
            ec = resolve(None, plant, law, {}, {})
            inputs, _ = vectors.record(ec)
            vectors.replay(ec, inputs[:2])
    for name in builtin_names():
        rb = load_rulebase(name)
        evaluate(rb, np.zeros((1, len(rb.inputs))))
    for tir in sorted((files("chassistune") / "data" / "tires").iterdir(), key=str):
        if tir.name.endswith(".tir"):
            _warm_tire(str(tir))


def _warm_tire(tir: str) -> None:
    """`chassistune tire` on the tyre file `tir` (with `--lateral` where it gives the lateral
    force's coefficients) and its forces over arrays (`mf_arrays.forces_n`: the curve a run
    fits when its tyre's polynomial is not cached yet)."""
    import numpy as np

    from chassistune.cli.tire import report_lines
    from chassistune.errors import InputError
    from chassistune.plants.mf_arrays import forces_n
    from chassistune.plants.tir import read_tir_file

    tire = read_tir_file(tir).tire
    forces_n(tire, -np.linspace(0.0, 1.0, 3), 0.0, tire.fnomin_n)
    try:
        report_lines(tir, lateral=True)
    except InputError:  # a file without the lateral force's coefficients
        report_lines(tir, lateral=False)


@click.command("warmup")
@click.option(
    "--processes",
    type=click.IntRange(1, 64),
    default=None,
    help="Worker processes that compile side by side [default: the machine's cores, at most 2].",
)
def warmup_command(processes: int | None) -> None:
    """Compile every kernel variant the commands can reach: every plant, preset, road and
    controller, both ECU modes, the C export (numba's disk cache; `make` runs this at
    installation, so that no documented command compiles at its first use). Removes first the
    caches of other versions of the sources unused for a week."""
    from chassistune._numba_cache import prune
    from chassistune.cli.choices import collect, store
    from chassistune.scenarios.warmup import warm_up

    cpu0 = time.process_time()
    for folder in prune():
        click.echo(f"removed {folder} (the cache of other sources, unused for a week)", err=True)
    store(collect())  # the choices `--help` lists

    def progress(entry: str, done: list[tuple[str, float]]) -> None:
        what = ", ".join(f"{name} {cpu_s:.0f} s" for name, cpu_s in done) or "from the cache"
        click.echo(f"warmup: {entry}: {what}", err=True)

    n = processes or max(1, min(2, os.cpu_count() or 1))
    report = warm_up(n, _warm_rest, progress)
    compiled_cpu_s = sum(cpu_s for _, cpu_s in report.compiled)
    click.echo(
        f"warmup: {len(report.compiled)} functions compiled ({compiled_cpu_s:.0f} s of CPU), "
        f"{report.cases} cases over {len(report.groups)} kernels run, in {report.wall_s:.1f} s "
        f"on {n} processes (this process: {time.process_time() - cpu0:.0f} s of CPU)"
    )
    for name, cpu_s in sorted(report.compiled, key=lambda x: -x[1]):
        click.echo(f"  {name}: {cpu_s:.1f} s of CPU")
