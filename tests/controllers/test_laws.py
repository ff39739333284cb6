"""The registry of control laws: kinds numbered once by registration, unknown names and kinds
refused loudly, the catalogue's ABS entries a view of it, the C of each law its module's."""

from __future__ import annotations

import dataclasses

import pytest

from chassistune.controllers import catalogue, laws, vehicle_specs
from chassistune.controllers.laws import registry
from chassistune.errors import InputError
from chassistune.export import c99


def test_kinds_are_registration_positions() -> None:
    for k, name in enumerate(laws.names()):
        assert laws.kind(name) == k and laws.by_kind(k).name == name


def test_an_unknown_law_is_refused_naming_the_known_ones() -> None:
    with pytest.raises(InputError) as err:
        laws.kind("lqr")
    assert err.value.field == "controller" and "known: none, pid" in err.value.problem
    with pytest.raises(ValueError, match="no control law of kind 99"):
        laws.by_kind(99)
    with pytest.raises(ValueError, match="no control law of kind -1"):
        laws.by_kind(-1)


def test_a_law_is_registered_once_and_only_the_last_may_go() -> None:
    with pytest.raises(ValueError, match="registered already"):
        laws.register(laws.get("pid"))
    with pytest.raises(ValueError, match="only the last registered law"):
        laws.unregister("pid")


@pytest.mark.parametrize("plant", [laws.ABS_WHEEL, laws.ABS_VEHICLE])
def test_the_catalogue_lists_the_laws_of_each_abs_plant(plant: str) -> None:
    specs = catalogue.for_plant(plant)
    assert specs == laws.for_plant(plant)
    assert [s.name for s in specs] == [n for n in laws.names() if laws.get(n).spec(plant)]
    for spec in specs:
        assert catalogue.get(plant, spec.name) is laws.get(spec.name).spec(plant)


def test_vehicle_specs_are_the_laws_vehicle_entries() -> None:
    assert vehicle_specs.names() == [s.name for s in laws.for_plant(laws.ABS_VEHICLE)]
    pid = vehicle_specs.get("pid")
    assert pid.default_gains() == {"kp": 1200.0, "ki": 0.0, "kd": 20.0}
    doubled = ("kp_f", "ki_f", "kd_f", "kp_r", "ki_r", "kd_r")
    assert vehicle_specs.per_axle(pid).gain_names == doubled


def test_an_abs_controller_outside_a_law_is_refused() -> None:
    spec = laws.get("pid").spec(laws.ABS_WHEEL)
    assert spec is not None
    with pytest.raises(ValueError, match="is a control law"):
        catalogue.register(type(spec)(laws.ABS_WHEEL, "lqr", "not a law"))


@pytest.mark.parametrize("name", laws.names())
def test_a_law_with_a_discrete_form_has_its_c_and_the_reverse(name: str) -> None:
    law = laws.get(name)
    assert (law.discrete is None) == (law.c is None)
    if law.c is not None:
        assert c99.c_form(name) is law.c and "double ct_step(" in law.c.step
        assert law.c.equations and all(line == line.strip() for line in law.c.equations)
        assert law.discrete is not None and law.discrete.controller == name
    else:
        with pytest.raises(ValueError, match="has no C form"):
            c99.c_form(name)


@pytest.mark.parametrize("name", laws.names())
def test_a_laws_memory_fits_the_kernels_lanes(name: str) -> None:
    law = laws.get(name)
    assert len(law.state) <= registry.slots("memory")
    assert len(law.ecu_inputs) <= registry.slots("ecu_inputs")
    assert law.discrete is None or len(law.discrete.state) <= registry.slots("discrete_state")


def test_the_lanes_are_sized_from_the_laws_and_a_larger_law_is_refused() -> None:
    most = max(len(laws.get(n).state) for n in laws.names())
    assert registry.slots("memory") == most
    big = dataclasses.replace(
        laws.get("threshold"), name="big", specs=(), state=("m",) * (most + 1)
    )
    with pytest.raises(ValueError, match="memory slots"):
        laws.register(big)
    assert "big" not in laws.names()


def test_the_fingerprint_names_the_registered_laws() -> None:
    before = registry.fingerprint()
    assert before == registry.fingerprint() and len(before) == 16


@pytest.mark.parametrize("name", laws.names())
def test_a_law_names_its_ecu_inputs_once(name: str) -> None:
    law = laws.get(name)
    if law.ecu is None:
        assert law.ecu_inputs == ()
    elif law.discrete is not None:
        assert law.ecu.inputs == () and law.ecu_inputs == law.discrete.inputs
    else:
        assert law.ecu_inputs == law.ecu.inputs != ()


def test_ecu_inputs_named_beside_a_discrete_form_are_refused() -> None:
    pid = laws.get("pid")
    assert pid.ecu is not None
    twice = dataclasses.replace(
        pid, name="pid-twice", specs=(), ecu=dataclasses.replace(pid.ecu, inputs=("slip",))
    )
    with pytest.raises(ValueError, match="names its ECU inputs twice"):
        laws.register(twice)
    assert "pid-twice" not in laws.names()


def test_code_compiled_over_the_registry_is_built_once_per_fingerprint() -> None:
    keys: list[int] = []

    def build(key: int) -> list[int]:
        keys.append(key)
        return [key]

    for_laws_now = registry.per_fingerprint(build)
    first = for_laws_now()
    assert for_laws_now() is first and keys == [int(registry.fingerprint()[:15], 16)]
    bang = laws.get("bang-bang")
    laws.register(dataclasses.replace(bang, name="bang-bang-copy", specs=()))
    try:
        assert for_laws_now() is not first and len(set(keys)) == 2
    finally:
        laws.unregister("bang-bang-copy")
    assert for_laws_now() is first and len(keys) == 2


def test_every_law_says_where_it_comes_from_and_whether_it_needs_the_road(cli) -> None:
    """`list controllers` shows each ABS law's source and its need of a target slip (the road
    knowledge), from the registry; a law without a source is refused at registration."""
    import json

    listed = json.loads(cli("list", "controllers", "--json").out)["controllers"]
    for plant in (laws.ABS_WHEEL, laws.ABS_VEHICLE):
        for item in listed[plant]:
            law = laws.get(item["name"])
            assert item["source"] == law.source != ""
            assert item["needs_target"] is law.needs_target
    assert laws.get("none").needs_target is False and laws.get("pid").needs_target is True
    text = cli("list", "controllers").out
    assert "needs no knowledge of the road" in text and "needs a target slip" in text
    nameless = dataclasses.replace(laws.get("pid"), name="sourceless", specs=(), source="")
    with pytest.raises(ValueError, match="source"):
        laws.register(nameless)
