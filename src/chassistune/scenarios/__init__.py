"""Scenarios: plant + preset + road + controller + objective -> cost(gains), metrics, trace."""
