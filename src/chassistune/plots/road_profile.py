"""Road displacement profiles against time (iabc-suspension Fig. 2: the random road input)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from chassistune.plots.style import pyplot, save


def plot_road_profiles(
    profiles: Sequence[tuple[str, np.ndarray, np.ndarray]], path: str, title: str
) -> None:
    """Each (label, time_s, road_m) as a line in mm against time, one panel."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for label, time_s, road_m in profiles:
        ax.plot(time_s, road_m * 1e3, lw=0.8, label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("road displacement z0 [mm]")
    ax.set_title(title)
    ax.legend(loc="upper right")
    fig.tight_layout()
    save(fig, path)
