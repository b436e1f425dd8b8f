"""Scenes are planned before anything runs, and only what is asked is computed."""

import json

import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.params.scene import default_scene, plan
from spectralshell.solvers import marginal


def spy_assemble(monkeypatch):
    calls = []
    real = marginal.assemble

    def spy(system, kind, n, form="real"):
        calls.append(kind)
        return real(system, kind, n, form)

    monkeypatch.setattr(marginal, "assemble", spy)
    return calls


def test_harmonic_only_scene_assembles_no_subharmonic_system(monkeypatch):
    calls = spy_assemble(monkeypatch)
    scene = {"model": "mathieu", "ask": ["floquet"], "params": {"kappa": 1.1, "nu": 0.1},
             "floquet": {"kind": "harmonic"}}
    results = ss.run_scene(scene)
    assert set(results) == {"floquet"} and results["floquet"].subharmonic is None
    assert calls and set(calls) == {"harmonic"}


def test_tasks_not_asked_are_not_planned():
    p = plan({"model": "mathieu", "ask": ["exponents"], "params": {"kappa": 1.0, "nu": 0.0},
              "exponents": {"tau": 0.2}, "tongues": {"kappa": "0:1:3"}})
    assert [t.name for t in p.tasks] == ["exponents"]


def test_default_scene_is_valid_and_shipped():
    p = plan(default_scene())
    assert p.model == "mathieu" and [t.name for t in p.tasks] == ["floquet", "tongues", "exponents"]


@pytest.mark.parametrize("scene,fragment", [
    ({"model": "mathieu", "params": {"kappa": "soft", "nu": 0}}, "kappa = 'soft' is invalid"),
    ({"model": "mathieu", "params": {"kappa": 1}, "ask": ["everything"]}, "ask = 'everything'"),
    ({"model": "mathieu", "params": {"kappa": 1}, "floquet": {"tol": "x"}}, "floquet.tol"),
    ({"model": "mathieu", "params": {"kappa": 1}, "colour": "red"}, "scene key 'colour'"),
    ({"params": {"kappa": 1}}, "no 'model'"),
    ("model = [", "invalid TOML"),
])
def test_bad_scenes_are_refused_before_computing(scene, fragment):
    with pytest.raises(ss.ParameterError, match=fragment):
        plan(scene)


def test_run_cli_on_a_toml_file(tmp_path, capsys):
    path = tmp_path / "s.toml"
    path.write_text('model = "mathieu"\nask = ["floquet"]\n[params]\nkappa = 0.25\nnu = 0.1\n'
                    '[floquet]\nkind = "subharmonic"\n')
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["floquet"]["harmonic"] is None
    assert data["floquet"]["subharmonic"]["tau_min"] == pytest.approx(0.2004369762968, abs=1e-12)
    bad = tmp_path / "bad.toml"
    bad.write_text('model = "mathieu"\n[params]\nkappa = "stiff"\n')
    assert main(["run", str(bad)]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
