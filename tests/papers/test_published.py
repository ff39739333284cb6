"""The papers' published numbers load as printed, with paper, source and unit."""

from __future__ import annotations

import pytest

from chassistune.errors import InputError
from chassistune.papers import keys, published


def test_every_paper_has_numbers_with_units_and_sources() -> None:
    for key in keys.PAPER_KEYS:
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


def test_values_keep_their_printed_digits() -> None:
    ice = published.lookup("derlsp-ao-abs", "stop_distance_m", "ice")
    assert ice.as_printed()["fuzzy PID"] == "47.2160" and ice.as_dict()["fuzzy PID"] == 47.216
    jump = published.lookup("deffao-vehicle-abs", "stop_time_s", "mu-jump").as_printed()
    assert jump["DEFFAO-fuzzy PID"] == "4.750"
    split = published.lookup("deffao-vehicle-abs", "stop_distance_m", "split-mu").as_printed()
    assert split["PID"] == "91.9460"
    fig4 = published.lookup("derlsp-ao-abs", "slip_settles_at_s", "dry-concrete").printed
    assert fig4 == ("1.00000",)  # 000 section 2.2: "1. 000 00 s"
    for key in keys.PAPER_KEYS:
        for q in published.quantities(key):
            assert q.values == tuple(float(v) for v in q.printed)


def test_unknown_paper_and_missing_quantity() -> None:
    with pytest.raises(InputError, match="unknown paper"):
        published.quantities("nope")
    with pytest.raises(KeyError):
        published.lookup("iabc-suspension", "stop_distance_m")
