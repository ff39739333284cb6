"""Shared figure setup: a non-interactive backend and one look for every figure."""

from __future__ import annotations

from typing import Any


def pyplot() -> Any:
    """matplotlib.pyplot on the Agg backend with our defaults."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    plt.rcParams.update(
        {
            "figure.dpi": 110,
            "axes.grid": True,
            "grid.alpha": 0.3,
            "axes.spines.top": False,
            "axes.spines.right": False,
            "font.size": 9,
            "legend.fontsize": 8,
            "legend.frameon": False,
        }
    )
    return plt


def save(fig: Any, path: str) -> None:
    """Write the figure atomically (a temporary file renamed into place) and close it."""
    from chassistune._io import atomic_path

    try:
        with atomic_path(path) as tmp:
            fig.savefig(tmp, bbox_inches="tight", format="png")
    finally:
        fig.clf()
        import matplotlib.pyplot as plt

        plt.close(fig)
