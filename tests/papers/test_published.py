"""The papers' published numbers load as printed, with paper, source and unit."""

from __future__ import annotations

import pytest

from chassistune.errors import InputError
from chassistune.papers import published


def test_every_paper_has_numbers_with_units_and_sources() -> None:
    for key in published.PAPER_KEYS:
        assert published.paper(key).citation
        qs = published.quantities(key)
        assert qs
        for q in qs:
            assert q.unit and q.source and len(q.labels) == len(q.values)


def test_values_are_quoted_exactly_as_published() -> None:
    q = published.lookup("derlsp-ao-abs", "stop_distance_m", "dry-concrete")
    assert q.source == "Table 2" and q.unit == "m"
    assert q.as_dict()["DERLSP-AO-PID"] == 24.8163
    t4 = published.lookup("deffao-vehicle-abs", "best_fitness_rosenbrock")
    assert t4.as_dict()["DEFFAO"] == 7.801e-14
    assert published.lookup("iabc-suspension", "iabc_objective").values == (2.7321,)


def test_unknown_paper_and_missing_quantity() -> None:
    with pytest.raises(InputError, match="unknown paper"):
        published.quantities("nope")
    with pytest.raises(KeyError):
        published.lookup("iabc-suspension", "stop_distance_m")
