"""Results in a notebook (issue 26): every result has a bounded, escaped HTML repr with its key
numbers, a labelled xarray Dataset (units, long names, params and provenance) that round-trips
through NetCDF, and the tables among them a pandas DataFrame."""

import dataclasses
import json
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import xarray as xr

from spectralshell.results.notebook import HTML_ROWS, HTML_WARNINGS, html_table, result_html
from spectralshell.results.records import Tip

from result_cases import CASES


def _key_numbers(res) -> list[str]:
    """The key numbers of a result as its summary prints them."""
    name = type(res).__name__
    if name in ("FloquetResult", "SpatialFloquetResult"):
        return [text for m in res.marginals() for text in (
            [f"{m.tau_min:.12g}", f"{m.error_estimate:.1e}"] if m.tau_min is not None else [])
            + ([f"{m.complete_to:.4g}"] if np.isfinite(m.complete_to) else [])]
    if name == "TonguesResult":
        return [f"{x:.12g}" for t in res.tips for x in (t.kappa, t.tau)]
    if name == "ExponentsResult":
        return [f"{g.real:+.12f}" for g in res.gamma] + [f"{res.error_estimate:.1e}"]
    if name == "StabilityResult":
        return [f"{t:.6g}" for mode in res.modes for k, v in mode.items()
                if k.startswith("tau_") for t in v]
    if name == "NaturalModesResult":
        return [f"{e:.1e}" for e in res.error_estimate] + (
            [d[0] for d in res.gamma_digits] if res.gamma_digits else
            [f"{g.real:+.12g}" for g in res.gamma])
    if name == "ResponseResult":
        return [f"{res.peak_x:.6g}", f"{res.peak_error:.1e}"]
    if name == "SteppedRun":
        return [f"{res.growth_rate:+.10f}", f"{res.frequency:.10f}", f"{res.error_estimate:.1e}"]
    return [f"{f.growth_rate:+.10f}" for f in res.fits] + [f"{f.frequency:.10f}" for f in res.fits]


@pytest.mark.parametrize("name", CASES)
def test_html_is_well_formed_with_the_key_numbers_of_the_summary(name, built):
    res = built(name)
    text = res._repr_html_()
    assert text.startswith("<") and type(res).__name__ in text
    ET.fromstring(text)  # well-formed: every tag closed, every entity escaped
    keys = _key_numbers(res)
    assert keys
    for key in keys:
        assert key in res.summary() and key in text, key
    for warning in res.warnings[:HTML_WARNINGS]:
        assert warning.replace(">", "&gt;").replace("<", "&lt;") in text


def _large_tongues(res, points: int, tips: int):
    """``res`` stretched to ``points`` kappa values and ``tips`` finger tips (no solve)."""
    rows = tuple(res.rows[i % len(res.rows)] for i in range(points))
    tip = Tip(kind="<sub>", kappa=0.5, tau=0.2, kappa_error=1e-14, tau_error=1e-13)
    return dataclasses.replace(res, kappa=np.linspace(0, 2, points), rows=rows,
                               tips=(tip,) * tips, warnings=("a & b",) * 20)


def test_html_of_a_2001_point_tongues_result_is_bounded_and_escaped(built):
    res = _large_tongues(built("tongues"), 2001, 40)
    text = res._repr_html_()
    ET.fromstring(text)
    assert len(text) < 6000
    assert text.count("<tr>") == HTML_ROWS + 1  # header and the first rows
    assert f"... {40 - HTML_ROWS} more rows" in text and "... 15 more (.warnings)" in text
    assert "&lt;sub&gt;" in text and "<sub>" not in text and "a &amp; b" in text


def test_html_table_counts_what_it_leaves_out():
    text = html_table(["a"], [[i] for i in range(HTML_ROWS + 1)])
    assert text.endswith("<p>... 1 more row (all in .to_xarray())</p>")
    assert "more" not in html_table(["a"], [[1]])
    assert "Warnings" not in result_html("R", "x", "", ())


def _netcdf(ds: xr.Dataset, tmp_path) -> xr.Dataset:
    path = tmp_path / "result.nc"
    ds.to_netcdf(path)
    with xr.open_dataset(path) as back:
        return back.load()


@pytest.mark.parametrize("name", CASES)
def test_dataset_round_trips_through_netcdf_with_units_and_provenance(name, built, tmp_path):
    res = built(name)
    ds = res.to_xarray()
    xr.testing.assert_identical(_netcdf(ds, tmp_path), ds)  # values and attrs
    assert ds.attrs["result_type"] == type(res).__name__ and ds.attrs["model"] == res.model
    assert json.loads(ds.attrs["params"]) == json.loads(json.dumps(res.to_dict()["params"]))
    assert json.loads(ds.attrs["provenance"])["version"] == res.provenance["version"]
    assert json.loads(ds.attrs["warnings"]) == list(res.warnings)
    for var in [*ds.data_vars.values(), *ds.coords.values()]:
        assert var.attrs.get("long_name"), var.name
        if var.dtype.kind == "f":
            assert var.attrs.get("units"), var.name


def _check_marginal(cell: xr.Dataset, m) -> None:
    """The Dataset ``cell`` (one kind, one kappa) holds the MarginalTau ``m``."""
    assert str(cell["kind"].values) == m.kind
    np.testing.assert_array_equal(cell["tau_min"], np.nan if m.tau_min is None else m.tau_min)
    assert bool(cell["has_tau"]) == (m.tau_min is not None)
    assert int(cell["n_temporal"]) == m.n_temporal
    assert float(cell["complete_to"]) == m.complete_to
    tau = cell["tau"].values
    np.testing.assert_array_equal(tau[:m.tau.size], m.tau)
    assert np.isnan(tau[m.tau.size:]).all()


@pytest.mark.parametrize("name", ["floquet", "floquet-none-below", "spatial-floquet"])
def test_floquet_dataset_holds_each_kind(name, built):
    res = built(name)
    ds = res.to_xarray()
    for i, m in enumerate(res.marginals()):
        _check_marginal(ds.isel(kind=i), m)
    assert ds["kind"].attrs["long_name"] == "Floquet kind" and "units" not in ds["kind"].attrs
    if name == "spatial-floquet":
        assert int(ds["n_spatial"]) == res.n_spatial
        assert json.loads(ds.attrs["n_spatial_previous"]) == res.n_spatial_previous


def test_tongues_dataset_is_the_grid_with_nan_where_no_tau_and_the_tips(built):
    res = built("tongues")
    ds = res.to_xarray()
    assert ds["tau_min"].dims == ("kappa", "kind") and ds["kappa"].attrs["units"] == "1"
    np.testing.assert_array_equal(ds["kappa"], res.kappa)
    for i, row in enumerate(res.rows):
        for j, kind in enumerate(res.kinds):
            _check_marginal(ds.isel(kappa=i, kind=j), row[kind])
    assert not ds["has_tau"].isel(kappa=0).any() and np.isnan(ds["tau_min"].isel(kappa=0)).all()
    assert list(ds["tip_kind"].values) == [t.kind for t in res.tips]
    np.testing.assert_array_equal(ds["tip_tau"], [t.tau for t in res.tips])
    np.testing.assert_array_equal(ds["tip_kappa_error"], [t.kappa_error for t in res.tips])
    frame = res.to_dataframe()
    assert frame.shape == (res.kappa.size * len(res.kinds), 6)
    assert list(frame.index.names) == ["kappa", "kind"]


def test_tongues_without_tips_leave_the_tip_variables_out(built, tmp_path):
    res = dataclasses.replace(built("tongues"), tips=())
    ds = res.to_xarray()
    assert "tip" not in ds.dims and "tip_kappa" not in ds
    xr.testing.assert_identical(_netcdf(ds, tmp_path), ds)


def test_exponents_dataset_splits_gamma_and_multipliers(built):
    res = built("exponents")
    ds = res.to_xarray()
    np.testing.assert_array_equal(ds["gamma_real"] + 1j * ds["gamma_imag"], res.gamma)
    np.testing.assert_array_equal(ds["multiplier_real"] + 1j * ds["multiplier_imag"],
                                  res.multipliers)
    assert float(ds["tau"]) == res.tau and int(ds["n_temporal"]) == res.n_temporal
    assert float(ds["error_estimate"]) == res.error_estimate
    assert res.to_dataframe().shape == (res.gamma.size, 4)


def test_stability_dataset_is_per_degree(built):
    res = built("stability")
    ds = res.to_xarray()
    assert list(ds["m"].values) == [mode["m"] for mode in res.modes]
    assert list(ds["unstable"].values) == [mode["unstable"] for mode in res.modes]
    assert list(ds["unstable_kind"].values) == [mode["kind"] or "" for mode in res.modes]
    for i, mode in enumerate(res.modes):
        for kind in ds["kind"].values:
            below = mode[f"tau_{kind}"]
            got = float(ds["tau_min"].sel(m=mode["m"], kind=kind))
            assert got == min(below) if below else np.isnan(got)
            tau = ds["tau_below"].sel(m=mode["m"], kind=kind).values
            np.testing.assert_array_equal(tau[:len(below)], below)
    frame = res.to_dataframe()
    assert frame.shape == (len(res.modes), 4 + ds.sizes["kind"])  # defined, unstable, proved,
    # kind
    assert "tau_min_subharmonic" in frame and frame["defined"].all()


@pytest.mark.parametrize("name", ["modes", "modes-digits", "modes-continued"])
def test_natural_modes_dataset_holds_each_mode(name, built):
    res = built(name)
    ds = res.to_xarray()
    np.testing.assert_array_equal(ds["decay_rate"], res.decay_rate)
    np.testing.assert_array_equal(ds["frequency"], res.frequency)
    np.testing.assert_array_equal(ds["error_estimate"], res.error_estimate)
    np.testing.assert_array_equal(ds["on_cut"], res.on_cut)
    if res.gamma_digits:
        assert list(ds["gamma_real_digits"].values) == [d[0] for d in res.gamma_digits]
    assert res.to_dataframe().shape[0] == res.gamma.size


def test_response_dataset_is_the_envelope_along_x(built):
    res = built("response")
    ds = res.to_xarray()
    np.testing.assert_array_equal(ds["x"], res.x)
    np.testing.assert_array_equal(ds["envelope"], res.envelope)
    np.testing.assert_array_equal(ds["x_cm"], res.to_cm(res.x))
    assert ds["x_cm"].attrs["units"] == "cm" and float(ds["peak_x"]) == res.peak_x
    assert np.isnan(float(ds["tau"])) and ds.attrs["kind"] == res.kind


def test_trajectory_dataset_is_the_time_series_and_fits(built):
    res = built("trajectory")
    ds = res.to_xarray()
    assert ds["radial"].dims == ("t", "mode")
    np.testing.assert_array_equal(ds["t"], res.times)
    np.testing.assert_array_equal(ds["radial"], res.radial)
    assert [(int(m), int(k)) for m, k in zip(ds["m"].values, ds["k"].values)] == list(res.modes)
    np.testing.assert_array_equal(ds["growth_rate"], [f.growth_rate for f in res.fits])
    assert "toroidal" not in ds  # no toroidal mode excited: its empty dimension is left out


def test_stepped_run_dataset_is_the_series_and_the_fit(built):
    res = built("stepped-run")
    ds = res.to_xarray()
    assert ds["values"].dims == ("t", "series") and list(ds["series"].values) == ["X^r", "X^theta"]
    np.testing.assert_array_equal(ds["values"], res.values)
    np.testing.assert_array_equal(ds["t"], res.times)
    assert float(ds["growth_rate"]) == res.growth_rate and ds.attrs["fitted"] == "X^r"


def test_html_and_a_floquet_result_do_not_import_xarray():
    code = ("import sys, spectralshell as ss; r = ss.floquet('mathieu', kappa=0.3, nu=0.1); "
            "r._repr_html_(); assert 'xarray' not in sys.modules and 'pandas' not in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True)
