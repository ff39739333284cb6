"""Convergence bands of a study's runs and the log-axis choice, shared by both report pages."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from chassistune import stats
from chassistune.studies.store import RunRecord


def convergence_bands(
    runs: Mapping[str, Sequence[RunRecord]],
) -> dict[str, tuple[int, dict[str, np.ndarray]]]:
    """Per label with recorded histories: (number of runs, `stats.convergence_band` on the union
    of their evaluation counts)."""
    out = {}
    for label, recs in runs.items():
        recs = [r for r in recs if r.history]
        if recs:
            grid = np.unique(
                np.concatenate([np.asarray(r.history_nfev, dtype=float) for r in recs])
            )
            out[label] = (
                len(recs),
                stats.convergence_band(
                    [r.history for r in recs], [r.history_nfev for r in recs], grid
                ),
            )
    return out


def log_scale_suits(values: Sequence[np.ndarray]) -> bool:
    """All finite values positive and spanning more than a factor 30."""
    v = np.concatenate([np.ravel(a) for a in values]) if values else np.zeros(0)
    v = v[np.isfinite(v)]
    return bool(v.size) and bool(np.all(v > 0)) and float(v.max() / v.min()) > 30.0
