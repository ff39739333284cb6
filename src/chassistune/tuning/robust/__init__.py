"""Robust tuning under uncertainty: one job per module.

- `spec`: uncertain parameters and the `[uncertainty]` table as frozen dataclasses;
- `sampling`: the training set (scrambled Sobol or Latin hypercube) and Monte Carlo sets;
- `aggregate`: a candidate's cost over K scenarios (mean, max, CVaR);
- `validation`: the pass criterion, the pass rate and the zero-failure certificate;
- `sensitivity`: first-order and total Sobol indices;
- `plant_params`: which plant, road and actuator parameters may vary, and `mu_scale`;
- `problem`: n candidates x K scenarios evaluated and aggregated (common random numbers).
"""
