"""The Sobol-index bar chart writes a PNG."""

from __future__ import annotations

from chassistune.plots.sensitivity import plot_sobol_indices


def test_the_bar_chart_is_a_png(tmp_path):
    path = tmp_path / "sobol.png"
    plot_sobol_indices(
        ["mass_kg", "mu_scale", "v0_m_s"],
        [0.1, 0.6, 0.2],
        [0.15, 0.7, 0.25],
        str(path),
        "distance ratio",
    )
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
    assert list(tmp_path.iterdir()) == [path]  # nothing half-written left beside it
