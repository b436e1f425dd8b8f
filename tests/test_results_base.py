"""Every result object has one base (spectralshell.results.base.Result): its JSON file round
trip, its summary (the text the command line prints), a short repr, and one-line refusals of
files that are not one of its kind."""

import dataclasses
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.results.base import REPR_LINES, Result
from spectralshell.results.floquet import FloquetResult
from spectralshell.results.records import RECORDS, MarginalTau, decode, encode, fields_of

from result_cases import CASES


def _same(a, b) -> bool:
    return json.dumps(a, sort_keys=True) == json.dumps(b, sort_keys=True)


def test_every_result_type_is_covered(built):
    kinds = {type(built(name)).__name__ for name in CASES}
    assert kinds == {"FloquetResult", "SpatialFloquetResult", "TonguesResult", "ExponentsResult",
                     "StabilityResult", "NaturalModesResult", "ResponseResult", "Trajectory",
                     "SteppedRun"}
    assert all(isinstance(built(name), Result) for name in CASES)


@pytest.mark.parametrize("name", CASES)
def test_save_then_load_gives_the_same_result(name, built, tmp_path):
    res = built(name)
    path = res.save(tmp_path / "result.json")
    stored = json.loads(path.read_text())
    assert stored["type"] == type(res).__name__ and stored["version"] == ss.__version__
    back = type(res).load(path)
    assert type(back) is type(res)
    assert _same(back.to_dict(), res.to_dict())
    assert _same(fields_of(back), fields_of(res))  # every field, not only the JSON form
    assert back.summary() == res.summary()
    for f in dataclasses.fields(res):
        value = getattr(res, f.name)
        if isinstance(value, np.ndarray):
            assert getattr(back, f.name).dtype == value.dtype
            assert getattr(back, f.name).shape == value.shape


@pytest.mark.parametrize("name", CASES)
def test_repr_is_short(name, built):
    res = built(name)
    text = repr(res)
    assert text.startswith(f"<{type(res).__name__}> ")
    assert len(text.splitlines()) <= REPR_LINES


def test_a_long_summary_is_cut_in_the_repr(built, monkeypatch):
    res = built("modes")
    monkeypatch.setattr(type(res), "summary", lambda self: "\n".join(map(str, range(50))))
    lines = repr(res).splitlines()
    assert len(lines) == REPR_LINES and "31 more lines" in lines[-1]


@pytest.mark.parametrize("name", CASES)
def test_summary_is_what_the_command_line_prints(name, built, capsys):
    assert main(CASES[name][1].split()) == 0
    assert capsys.readouterr().out == built(name).summary() + "\n"


@pytest.mark.parametrize("name", CASES)
def test_load_refuses_a_file_of_another_type(name, built, tmp_path):
    res = built(name)
    other = built("floquet" if type(res).__name__ == "ExponentsResult" else "exponents")
    path = other.save(tmp_path / "other.json")
    with pytest.raises(ParameterError, match=f"holds a {type(other).__name__}, not a "
                                             f"{type(res).__name__}") as info:
        type(res).load(path)
    assert str(path) in str(info.value) and "\n" not in str(info.value)


def test_a_subclass_loads_as_its_base(built, tmp_path):
    res = built("spatial-floquet")
    back = FloquetResult.load(res.save(tmp_path / "spatial.json"))
    assert type(back) is type(res) and _same(back.to_dict(), res.to_dict())


def _damaged(res, tmp_path, change) -> str:
    """The one-line message of loading ``res`` saved, with ``change`` applied to its text."""
    path = res.save(tmp_path / "result.json")
    path.write_text(change(path.read_text()))
    with pytest.raises(ParameterError) as info:
        type(res).load(path)
    message = str(info.value)
    assert str(path) in message and "\n" not in message
    return message


def _edit(edit):
    def change(text):
        data = json.loads(text)
        edit(data["fields"])
        return json.dumps(data)
    return change


@pytest.mark.parametrize("name", CASES)
def test_load_refuses_truncated_json(name, built, tmp_path):
    assert "is not valid JSON" in _damaged(built(name), tmp_path, lambda t: t[:len(t) // 2])


@pytest.mark.parametrize("name", CASES)
def test_load_refuses_a_removed_field(name, built, tmp_path):
    message = _damaged(built(name), tmp_path, _edit(lambda f: f.pop("model")))
    assert "lacks field 'model'" in message


@pytest.mark.parametrize("name", CASES)
def test_load_refuses_a_field_of_the_wrong_kind(name, built, tmp_path):
    message = _damaged(built(name), tmp_path, _edit(lambda f: f.update(params=5)))
    assert "damaged" in message


def test_load_names_a_damaged_nested_record(built, tmp_path):
    message = _damaged(built("floquet"), tmp_path,
                       _edit(lambda f: f["harmonic"].pop("tau")))
    assert "field 'harmonic' is damaged" in message and "'tau'" in message


@pytest.mark.parametrize("change, what", [
    (_edit(lambda f: f.update(extra=1)), "has unknown field 'extra'"),
    (lambda t: "[1, 2]", "is not a saved spectralshell result"),
    (lambda t: t.replace('"__type__": "ndarray"', '"__type__": "nonsense"', 1), "damaged"),
])
def test_load_refuses_other_damage(change, what, built, tmp_path):
    assert what in _damaged(built("tongues"), tmp_path, change)


@pytest.mark.parametrize("target", ["result.txt", "."])
def test_save_refuses_a_path_that_is_not_a_json_file(target, built, tmp_path):
    with pytest.raises(ParameterError, match="path = "):
        built("exponents").save(tmp_path / target)


def test_load_refuses_a_missing_file(tmp_path):
    path = tmp_path / "absent.json"
    with pytest.raises(ParameterError, match="cannot be read") as info:
        FloquetResult.load(path)
    assert str(path) in str(info.value)


def test_records_round_trip_through_their_dict():
    m = MarginalTau(kind="subharmonic", tau=np.array([0.25, 1.5]), tau_min=0.25, n_temporal=15,
                    n_previous=9, error_estimate=1e-15, method="structured")
    back = MarginalTau.from_dict(json.loads(json.dumps(m.to_dict(), allow_nan=False)))
    assert _same(back.to_dict(), m.to_dict()) and back.complete_to == np.inf
    assert set(RECORDS) == {"MarginalTau", "Tip", "Boundary", "Exponents", "ModeRoots",
                            "RateFit", "ContinuedModes"}
    b = RECORDS["Boundary"](kind="harmonic", kappa=np.array([0.9, 1.0]), tau=np.array([0.3, 0.0]))
    back = RECORDS["Boundary"].from_dict(json.loads(json.dumps(b.to_dict(), allow_nan=False)))
    assert back.kind == b.kind and _same(back.to_dict(), b.to_dict())


@settings(max_examples=60, deadline=None)
@given(hnp.arrays(st.sampled_from([np.float64, np.complex128, np.int64, np.bool_]),
                  hnp.array_shapes(min_dims=0, max_dims=3, min_side=0, max_side=4)))
def test_arrays_keep_values_dtype_and_shape(array):
    back = decode(json.loads(json.dumps(encode((array, {"a": array})), allow_nan=False)), {})
    for value in (back[0], back[1]["a"]):
        assert value.dtype == array.dtype and value.shape == array.shape
        np.testing.assert_array_equal(value, array)
