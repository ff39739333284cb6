"""The bench's scaling curves: cost per candidate-step against population, and a tuning run's
time against population x iterations (`chassistune bench [--only scaling] --plot FILE`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from chassistune.plots.style import pyplot, save


def plot_scaling(
    per_step: Mapping[str, Sequence[tuple[int, float]]],
    tuning: Mapping[str, Sequence[tuple[int, float]]],
    path: str,
) -> None:
    """ns per candidate-step per model (left) and tuning seconds per series (right), log-log."""
    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4))
    for model, pts in per_step.items():
        if pts:
            left.plot(*zip(*pts, strict=True), marker="o", label=model)
    left.set(xscale="log", yscale="log", xlabel="population", ylabel="CPU ns per candidate-step")
    above = {"fontsize": 8, "loc": "lower center", "bbox_to_anchor": (0.5, 1.0), "ncol": 3}
    left.legend(**above)
    for label, pts in tuning.items():
        right.plot(
            *zip(*pts, strict=True), marker="o" if label.startswith("wall") else "s", label=label
        )
    right.set(xscale="log", yscale="log", xlabel="population x iterations", ylabel="tuning run, s")
    if tuning:
        right.legend(**{**above, "ncol": 2})
    fig.tight_layout()
    save(fig, path)
