import pytest

from rotaflex.core.errors import InputError
from rotaflex.sweep import as_cases, grid_cases, parse_vary

BASE = {"drive": {"speed_rpm": 1000.0, "teeth": 28, "label": "a", "on": True}, "x": 1.0}


def test_range_and_list_forms():
    assert parse_vary("drive.speed_rpm=1000:3000:3") == ("drive.speed_rpm", [1000, 2000, 3000])
    key, values = parse_vary("x=0:1:5")
    assert key == "x" and values == [0.0, 0.25, 0.5, 0.75, 1.0]
    assert parse_vary("x = 0.1:0.1:1") == ("x", [0.1])
    assert parse_vary("drive.label=a,'b c',true,3,2.5") == (
        "drive.label",
        ["a", "b c", True, 3, 2.5],
    )
    assert parse_vary("x=1e3:2e3:2") == ("x", [1000.0, 2000.0])


@pytest.mark.parametrize(
    "spec, field",
    [
        ("speed", "--vary"),  # no '='
        ("=1:2:3", "--vary"),  # no key
        ("a..b=1,2", "--vary"),  # empty path part
        ("x=1:2", "--vary x"),  # two fields
        ("x=1:2:0", "--vary x"),  # N < 1
        ("x=1:2:2.5", "--vary x"),  # N not an integer
        ("x=a:2:3", "--vary x"),  # START not a number
        ("x=1:2:1", "--vary x"),  # N = 1 with START != STOP
        ("x=1,,2", "--vary x"),  # empty entry
    ],
)
def test_bad_vary_specs_name_the_option(spec, field):
    with pytest.raises(InputError) as err:
        parse_vary(spec)
    assert err.value.field == field


def test_grid_is_cartesian_first_key_slowest_and_typed():
    cases = grid_cases(BASE, {"drive.speed_rpm": [1000, 2000], "drive.teeth": [20.0, 30.0, 40.0]})
    assert [c.params for c in cases[:3]] == [
        {"drive.speed_rpm": 1000.0, "drive.teeth": 20},
        {"drive.speed_rpm": 1000.0, "drive.teeth": 30},
        {"drive.speed_rpm": 1000.0, "drive.teeth": 40},
    ]
    assert len(cases) == 6
    c = cases[4]
    assert c.data["drive"]["speed_rpm"] == 2000.0 and isinstance(c.data["drive"]["speed_rpm"], float)
    assert c.data["drive"]["teeth"] == 30 and isinstance(c.data["drive"]["teeth"], int)
    assert c.data["drive"]["label"] == "a" and c.data["x"] == 1.0
    assert BASE["drive"]["speed_rpm"] == 1000.0  # base not mutated
    assert len({c.id for c in cases}) == 6


def test_case_ids_are_stable_and_depend_on_the_data():
    a = grid_cases(BASE, {"x": [1.0, 2.0]})
    b = grid_cases(BASE, {"x": [1.0, 2.0]})
    assert [c.id for c in a] == [c.id for c in b]
    other = dict(BASE, drive={**BASE["drive"], "teeth": 29})
    c = grid_cases(other, {"x": [1.0, 2.0]})
    assert all(x.id != y.id for x, y in zip(a, c, strict=True))
    assert a[0].id.startswith("0000-") and a[1].id.startswith("0001-")


def test_missing_key_is_named():
    with pytest.raises(InputError) as err:
        grid_cases(BASE, {"drive.speed": [1.0]})
    assert err.value.field == "drive.speed" and "drive.speed" in str(err.value)


@pytest.mark.parametrize(
    "vary",
    [
        {"drive.teeth": [20.5]},  # non-integral for an int key
        {"drive.label": [1, 2]},  # number for a string key
        {"drive.on": [1]},  # number for a bool key
        {"x": [1.0, 1]},  # repeated value
        {"x": []},  # nothing to sweep
        {"drive": [1.0]},  # a table, not a value
        {"domain": ["gear"]},
    ],
)
def test_wrong_values_are_rejected(vary):
    with pytest.raises(InputError):
        grid_cases({**BASE, "domain": "rotor"}, vary)


def test_plain_mapping_cases_and_duplicates():
    cases = as_cases([{"x": 1.0, "tag": "a", "arr": [1, 2]}, {"x": 2.0, "tag": "b", "arr": [1]}])
    assert cases[0].params == {"x": 1.0, "tag": "a"} and cases[0].data["arr"] == [1, 2]
    with pytest.raises(InputError):
        as_cases([cases[0], cases[0]])


def test_array_entries_and_broadcast():
    base = {"operation": {"speed_rpm": [4000.0, 4040.0], "torque": 1.0}}
    both = grid_cases(base, {"operation.speed_rpm": [1000, 2000]})
    assert [c.data["operation"]["speed_rpm"] for c in both] == [[1000.0, 1000.0], [2000.0, 2000.0]]
    assert both[1].params == {"operation.speed_rpm": 2000.0}
    one = grid_cases(base, {"operation.speed_rpm[1]": [5000.0]})
    assert one[0].data["operation"]["speed_rpm"] == [4000.0, 5000.0]
    assert base["operation"]["speed_rpm"] == [4000.0, 4040.0]
    with pytest.raises(InputError) as err:
        grid_cases(base, {"operation.speed_rpm[2]": [1.0]})
    assert err.value.field == "operation.speed_rpm[2]"
    with pytest.raises(InputError):
        grid_cases(base, {"operation.torque[0]": [1.0]})


def test_index_inside_the_path_array_of_tables():
    base = {"loads": [{"kind": "torque", "duration": 6.0}, {"kind": "force", "duration": 2.0}]}
    cases = grid_cases(base, {"loads[1].duration": [1.0, 3.0]})
    assert [c.data["loads"][1]["duration"] for c in cases] == [1.0, 3.0]
    assert all(c.data["loads"][0] == base["loads"][0] for c in cases)
    assert base["loads"][1]["duration"] == 2.0
    with pytest.raises(InputError) as err:
        grid_cases(base, {"loads[2].duration": [1.0]})
    assert err.value.field == "loads[2].duration"
    with pytest.raises(InputError):
        grid_cases(base, {"loads[0].length": [1.0]})
