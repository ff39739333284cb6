"""`chassistune warmup`: compile every kernel now (cached on disk) instead of at first use."""

from __future__ import annotations

import time

import click


@click.command("warmup")
def warmup_command() -> None:
    """Compile every plant's and controller's kernels (numba's disk cache; `make` runs this at
        installation, so that the first `reproduce` or `tune` starts at once), after removing the
    caches of other versions of the sources unused for a week."""
    from chassistune._numba_cache import prune
    from chassistune.cli.choices import collect, store
    from chassistune.scenarios.warmup import warm_up

    t0 = time.perf_counter()
    for folder in prune():
        click.echo(f"removed {folder} (the cache of other sources, unused for a week)", err=True)
    store(collect())  # the choices `--help` lists
    done = warm_up(lambda pair: click.echo(f"compiled {pair}", err=True))
    click.echo(
        f"warmup: {len(done)} plant/controller pairs compiled or loaded from the cache "
        f"in {time.perf_counter() - t0:.1f} s"
    )
