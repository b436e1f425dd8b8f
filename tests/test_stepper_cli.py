"""`spectralshell simulate` and `ss.simulate`: scene handling, JSON shape, files, errors."""

import json
import subprocess
import sys

import numpy as np
import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError

PNG = b"\x89PNG\r\n\x1a\n"
MODE_KEYS = {"m", "k", "growth_rate", "frequency", "error_estimate"}


def test_api_trajectory_and_npz(tmp_path):
    """Two degrees, three modes (orders of one degree share one system and its fit); the JSON
    form has exactly the keys of the issue; the NPZ holds the same arrays."""
    traj = ss.simulate({"params": {"kappa": 1.0, "nu": 0.05},
                        "initial": {"shape": "2:0, 3:1:0.02, 3:-2"},
                        "simulate": {"t_end": 12.0, "n_radial": 24}})
    assert traj.modes == ((2, 0), (3, -2), (3, 1))
    assert traj.radial.shape == (traj.times.size, 3) and traj.toroidal.shape[1] == 0
    np.testing.assert_allclose(traj.radial[0], [0.05, 0.05, 0.02])
    # (3, -2) and (3, 1) obey the same equation: proportional coefficients
    np.testing.assert_allclose(traj.coefficient(3, 1) / 0.02, traj.coefficient(3, -2) / 0.05,
                               rtol=1e-10, atol=1e-13)
    data = traj.to_dict()
    assert set(data) == {"model", "params", "modes"} and data["model"] == "sphere"
    assert all(set(m) == MODE_KEYS for m in data["modes"]) and len(data["modes"]) == 3
    assert {"kappa", "nu", "tau"} <= set(data["params"])
    path = tmp_path / "t.npz"
    traj.write_npz(path)
    with np.load(path) as z:
        np.testing.assert_array_equal(z["radial"], traj.radial)
        assert list(z["m"]) == [2, 3, 3] and json.loads(str(z["metadata"]))["model"] == "sphere"


def test_cli_sphere_flags_json_and_files(tmp_path, capsys):
    """Inviscid case 2 (the Mathieu equation of m = 2 inside its subharmonic finger)."""
    png, npz = tmp_path / "f.png", tmp_path / "f.npz"
    code = main(["simulate", "sphere", "--m", "2", "--kappa", "0.06", "--nu", "0", "--tau",
                 "0.25", "--t-end", "60", "--scheme", "sbdf3", "--png", str(png), "--npz",
                 str(npz), "--json"])
    out = capsys.readouterr().out.strip().splitlines()
    assert code == 0 and len(out) == 1
    data = json.loads(out[0])
    assert set(data) == {"model", "params", "modes"}
    (mode,) = data["modes"]
    assert set(mode) == MODE_KEYS and (mode["m"], mode["k"]) == (2, 0)
    assert mode["growth_rate"] > 0 and mode["frequency"] == pytest.approx(0.5)   # subharmonic
    for path in (png, tmp_path / "f_shape.png"):
        assert path.read_bytes()[:8] == PNG
    assert npz.stat().st_size > 0


def test_cli_scene_file(tmp_path, capsys):
    scene = tmp_path / "decay.toml"
    scene.write_text(f"""
model = "sphere"
[params]
kappa = 1.0
nu = 0.05
[initial]
shape = "0.05*sin(theta)**2*cos(2*phi)"
[simulate]
t_end = 10.0
n_radial = 24
[output]
dir = "{tmp_path / 'out'}"
""")
    assert main(["simulate", str(scene)]) == 0
    text = capsys.readouterr().out
    assert "(m, k) = (2, 2)" in text
    for name in ("decay.json", "decay.png", "decay_shape.png", "decay.npz"):
        assert (tmp_path / "out" / name).stat().st_size > 0
    data = json.loads((tmp_path / "out" / "decay.json").read_text())
    assert [(m["m"], m["k"]) for m in data["modes"]] == [(2, 2)]
    assert data["modes"][0]["growth_rate"] < 0


@pytest.mark.parametrize("argv,needle", [
    (["simulate", "sphere", "--kappa", "1", "--nu", "0.1", "--t-end", "5"], "--m"),
    (["simulate", "sphere", "--m", "2", "--nu", "0.1", "--t-end", "5"], "--kappa"),
    (["simulate", "sphere", "--m", "1", "--kappa", "1", "--nu", "0.1", "--t-end", "5"], "degree m"),
    (["simulate", "sphere", "--m", "2", "--kappa", "1", "--nu", "0.1", "--t-end", "5",
      "--scheme", "rk4"], "scheme"),
    (["simulate", "sphere", "--shape", "2:0", "--kappa", "1", "--nu", "-1", "--t-end", "5"], "nu"),
    (["simulate", "sphere", "--shape", "cos(psi)", "--kappa", "1", "--nu", "0.1", "--t-end", "5"],
     "psi"),
])
def test_cli_bad_input_exits_2_with_one_line(argv, needle, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and needle in err[0]


def test_api_bad_scene():
    with pytest.raises(ParameterError, match="t_end"):
        ss.simulate({"params": {"kappa": 1, "nu": 0.1}, "initial": {"shape": "2:0"}})
    with pytest.raises(ParameterError, match="unknown"):
        ss.simulate({"params": {"kappa": 1, "nu": 0.1}, "initial": {"shape": "2:0"},
                     "simulate": {"t_end": 1, "steps": 3}})


def test_cli_stdout_is_one_json_object_in_a_fresh_process():
    """shtns.py prints a banner when imported; an expression shape (analysed with SHTns) must
    still leave exactly one JSON object on stdout."""
    done = subprocess.run([sys.executable, "-m", "spectralshell", "simulate", "sphere", "--shape",
                           "0.1*cos(theta)**3", "--kappa", "1", "--nu", "0", "--t-end", "20",
                           "--json"], capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.strip().splitlines()
    assert len(lines) == 1 and [m["m"] for m in json.loads(lines[0])["modes"]] == [3]
