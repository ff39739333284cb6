"""The papers' keys, written once: each paper module's `KEY`, the published numbers
(`data/paper_results.toml`), the report's sections and `chassistune reproduce PAPER` use these.
A leaf: importing it imports nothing else."""

DERLSP_AO_ABS = "derlsp-ao-abs"
IABC_SUSPENSION = "iabc-suspension"
DEFFAO_VEHICLE_ABS = "deffao-vehicle-abs"
FUZZY_IMMUNE_ABS = "fuzzy-immune-abs"

PAPER_KEYS = (DERLSP_AO_ABS, IABC_SUSPENSION, DEFFAO_VEHICLE_ABS, FUZZY_IMMUNE_ABS)
"""Every paper, in the report's order."""
