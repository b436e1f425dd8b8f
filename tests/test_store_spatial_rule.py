"""Stores of sweeps that refine M per point (the cochlea without n_spatial) name the stopping rule
of that refinement in each chunk's record (a NetCDF file in its digest): chunks written under
another rule, or before records named one (the pair rule, which two coarse M agreeing by chance
could pass; solvers/spatial_refinement.py), are refused on reading and recomputed on a rerun,
never mixed with this rule's values; damage is still damage."""

import json
import shutil

import pytest

from spectralshell import cli
from spectralshell.errors import StoreDamaged
from spectralshell.params.sweep_grid import sweep_spec
from spectralshell.runner import open_sweep, run_sweep
from spectralshell.runner.integrity import dataset_digest, record_path, record_text
from spectralshell.runner.layout import chunks, region
from spectralshell.runner.solve import NATURAL_RULE, spatial_rule
from spectralshell.runner.store import read_zarr, stored_variables
from spectralshell.solvers.spatial_refinement import SPATIAL_RULE

SCENE = {"model": "cochlea", "ask": ["tau_min"], "params": {"mu": 2.0},
         "grid": {"frequency": [400.0, 600.0], "sigma": [1e7], "kind": ["subharmonic"]},
         "tau_min": {"n_temporal": 6, "tau_max": 0.5}, "sweep": {"chunk": 1}}
SPEC = sweep_spec(SCENE)
FIRST = chunks(SPEC)[0]
EARLIER = "earlier stopping rule of the refinement in M"


def tree(path):
    return {str(p.relative_to(path)): p.read_bytes() for p in sorted(path.rglob("*"))
            if p.is_file()}


@pytest.fixture(scope="module")
def clean(tmp_path_factory):
    base = tmp_path_factory.mktemp("rule")
    run_sweep(SCENE, executor="serial", out=base / "map.zarr")
    run_sweep(SCENE, executor="serial", out=base / "map.nc")
    return base


def _rewrite_record(store, rule, alter=False):
    """The first chunk's record as code naming ``rule`` (None: no rule) would have written it
    for the chunk's values (``alter``: for other values, as if a file changed since)."""
    arrays = read_zarr(store, SPEC)[1].arrays
    block = {name: arrays[name][region(SPEC, FIRST)].copy() for name in stored_variables(SPEC)}
    if alter:
        block["tau_min"] += 1e-3
    record_path(store, SPEC, FIRST).write_text(record_text(SPEC, FIRST, block, rule))


def test_records_name_the_rule_only_where_m_is_refined(clean):
    record = json.loads(record_path(clean / "map.zarr", SPEC, FIRST).read_text())
    assert record["spatial_rule"] == SPATIAL_RULE
    fixed = sweep_spec({**SCENE, "params": {"mu": 2.0, "n_spatial": 16}})
    assert not fixed.refines_spatial
    block = {name: 0 for name in stored_variables(fixed)}
    assert "spatial_rule" not in json.loads(record_text(fixed, chunks(fixed)[0], block,
                                                        SPATIAL_RULE))


@pytest.mark.parametrize("rule", [None, "pair M/2, M"])
def test_chunks_of_an_earlier_rule_are_refused_then_recomputed(rule, clean, tmp_path, capsys):
    store = tmp_path / "map.zarr"
    shutil.copytree(clean / "map.zarr", store)
    _rewrite_record(store, rule)
    with pytest.raises(StoreDamaged, match=EARLIER + r".*recompute its 1 finished chunks"):
        open_sweep(store)
    assert cli.main(["plot", str(store), "--png", str(tmp_path / "m.png")]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and EARLIER in err and "damaged" not in err

    run = run_sweep(SCENE, executor="serial", out=store)
    assert (run.computed, run.skipped, run.outdated, run.damaged) == (1, 1, 1, 0)
    line = cli._sweep_text(run.summary())
    assert "\n" not in line and "1 of them in outdated chunks of the store" in line
    assert tree(store) == tree(clean / "map.zarr")  # this rule's values and records throughout


def test_an_earlier_rules_record_of_other_values_is_damage(clean, tmp_path):
    store = tmp_path / "map.zarr"
    shutil.copytree(clean / "map.zarr", store)
    _rewrite_record(store, None, alter=True)
    with pytest.raises(StoreDamaged, match="is damaged: 1 of 2 chunks"):
        open_sweep(store)
    run = run_sweep(SCENE, executor="serial", out=store)
    assert (run.computed, run.outdated, run.damaged) == (1, 0, 1)
    assert tree(store) == tree(clean / "map.zarr")


def test_a_netcdf_sweep_of_an_earlier_rule_is_refused_then_recomputed(clean, tmp_path):
    import xarray as xr

    path = tmp_path / "map.nc"
    with xr.open_dataset(clean / "map.nc") as ds:
        old = ds.load()
    assert old.attrs["spatial_rule"] == SPATIAL_RULE
    arrays = {name: old[name].values.astype(dtype)
              for name, dtype in stored_variables(SPEC).items()}
    del old.attrs["spatial_rule"]  # as written before files named the rule
    old.attrs["data_sha256"] = dataset_digest(SPEC, arrays, None)
    old.to_netcdf(path)
    with pytest.raises(StoreDamaged, match=EARLIER + r" \(the pair M/2, M alone.*to recompute it"):
        open_sweep(path)
    run = run_sweep(SCENE, executor="serial", out=path)
    assert (run.computed, run.outdated, run.damaged) == (2, 2, 0)
    again, fresh = open_sweep(path), open_sweep(clean / "map.nc")
    assert again.attrs["spatial_rule"] == SPATIAL_RULE
    for name in stored_variables(SPEC):
        xr.testing.assert_equal(again[name], fresh[name])


def test_a_minimum_map_names_its_basis_and_recomputes_chunks_of_cosine_blocks(tmp_path):
    """A minimum-tau map's records name the natural-mode basis of its blocks as well
    (runner.solve.spatial_rule); a chunk recorded under the window rule alone (written when
    every point used cosine-mode blocks) is outdated: refused, then recomputed."""
    scene = {**SCENE, "grid": {"frequency": [400.0], "sigma": [1e8]},
             "tau_min": {**SCENE["tau_min"], "over_kinds": "minimum"}}
    spec = sweep_spec(scene)
    store = tmp_path / "min.zarr"
    run_sweep(scene, executor="serial", out=store)
    first = chunks(spec)[0]
    record = json.loads(record_path(store, spec, first).read_text())
    assert record["spatial_rule"] == spatial_rule(spec) == f"{SPATIAL_RULE}; {NATURAL_RULE}"
    clean = tree(store)
    arrays = read_zarr(store, spec)[1].arrays
    block = {name: arrays[name][region(spec, first)].copy() for name in stored_variables(spec)}
    record_path(store, spec, first).write_text(record_text(spec, first, block, SPATIAL_RULE))
    with pytest.raises(StoreDamaged, match=EARLIER + r".*cosine-mode blocks at every point"):
        open_sweep(store)
    run = run_sweep(scene, executor="serial", out=store)
    assert (run.computed, run.outdated, run.damaged) == (2, 2, 0)  # the point's two kinds
    assert tree(store) == clean
