"""Tongues and stability state what their empty answers and verdicts rest on (issue 23,
section 2): an empty row of a diagram the zero count cannot prove is listed as uncertified,
a stability verdict is given only where the list below tau is certified and the parity rule
decides; checked against the Floquet exponents, and the CLI exits 1 in one line."""

import contextlib
import io
import json

import pytest

import spectralshell as ss
from spectralshell.cli import main
from spectralshell.plots import ince_strutt
from spectralshell.plots._canvas import UNCERTIFIED_LABEL, subplots
from spectralshell.solvers import marginal

FIBRE = {"kappa": 0.3, "nu": 0.001}
#: The viscous sphere over kappa at m = 2, nu = 0.05: no tau <= 1/2 of either kind.
TONGUES = {"kappa": "0.1:1.5:5", "m": 2, "nu": 0.05, "tau_max": 0.5, "tips": False,
           "boundaries": False, "workers": 1}


def _uncertifiable(monkeypatch):
    """No empty answer can be proved: the contour path declines, the zero count fails."""
    monkeypatch.setattr(marginal, "smallest_real_tau", lambda *args, **kwargs: None)
    monkeypatch.setattr(marginal, "none_up_to", lambda hill, tau_max, solves=None: False)


def run(argv):
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        rc = main(argv)
    return rc, out.getvalue(), err.getvalue()


def lead_growth(model, tau, **params):
    """max Re gamma of the Floquet exponents (the oracle: unstable iff > 0)."""
    return float(ss.exponents(model, tau=tau, count=1, **params).gamma[0].real)


def test_viscous_verdicts_agree_with_the_exponents_or_are_marked():
    """The fibre at tau = 0.9: m = 2 (one tau of each kind below) is unstable, as its leading
    exponent (Re gamma = 0.38) says; m = 3 has two subharmonic tau below (0.541 and, found
    once the list is certified up to tau, 0.714): the parity rule would say stable, but
    Re gamma = 1.12 > 0 -- the point is marked not proved, never stable. At tau = 0.45 m = 4
    (none below, certified) is stable, with Re gamma < 0."""
    res = ss.stability("fibre", tau=0.9, m="2:3", **FIBRE)
    m2, m3 = res.modes
    assert m2["unstable"] and m2.get("proved", True)
    assert lead_growth("fibre", 0.9, m=2, **FIBRE) > 0
    assert m3["proved"] is False and "parity rule" in m3["reason"]
    assert len(m3["tau_subharmonic"]) == 2
    assert lead_growth("fibre", 0.9, m=3, **FIBRE) > 0
    assert res.unproved() == 1 and res.unproved_note() in res.warnings
    stable = ss.stability("fibre", tau=0.45, m=4, **FIBRE).modes[0]
    assert not stable["unstable"] and stable.get("proved", True)
    assert not stable["tau_harmonic"] and not stable["tau_subharmonic"]
    assert lead_growth("fibre", 0.45, m=4, **FIBRE) < 0


def test_unprovable_stable_verdict_is_marked_or_refused(monkeypatch):
    """With the zero count made to fail, no point with nothing below tau is called stable:
    several points are kept with proved False, one point raises, and the CLI prints the
    table and exits 1 with one line."""
    _uncertifiable(monkeypatch)
    res = ss.stability("fibre", tau=0.45, m="4:5", **FIBRE)
    assert [mode["proved"] for mode in res.modes] == [False, False]
    assert all("zero count cannot prove" in mode["reason"] for mode in res.modes)
    with pytest.raises(ss.ConvergenceError, match="zero count cannot prove"):
        ss.stability("fibre", tau=0.45, m=4, **FIBRE)
    rc, out, err = run(["stability", "fibre", "--tau", "0.45", "--m", "4:5", "--kappa", "0.3",
                        "--nu", "0.001", "--json"])
    assert rc == 1 and [m["proved"] for m in json.loads(out)["modes"]] == [False, False]
    assert len(err.strip().splitlines()) == 1 and "not proved" in err


def test_tongue_rows_certified_or_listed(monkeypatch):
    """Empty rows state complete_to = tau_max and none is uncertified; with the count made to
    fail every row is listed as uncertified, drawn with red crosses named in the legend, and
    the CLI exits 1 with one line."""
    res = ss.tongues("sphere", **TONGUES)
    assert not res.uncertified
    for row in res.rows:
        for kind in res.kinds:
            assert row[kind].tau_min is None and row[kind].complete_to == 0.5
    _uncertifiable(monkeypatch)
    res = ss.tongues("sphere", **TONGUES)
    assert len(res.uncertified) == 10 and res.uncertified_note() in res.warnings
    assert res.to_dict()["uncertified"][0] == {"kappa": 0.1, "kind": "harmonic"}
    fig, ax = subplots(figsize=(6.0, 4.5))
    ince_strutt.draw(ax, res, tau_max=1.0)
    assert UNCERTIFIED_LABEL in [t.get_text() for t in ax.get_legend().get_texts()]
    rc, out, err = run(["tongues", "sphere", "--kappa", "0.1:1.5:5", "--m", "2", "--nu", "0.05",
                        "--tau-max", "0.5", "--no-tips", "--no-boundaries", "--workers", "1",
                        "--json"])
    assert rc == 1 and len(json.loads(out)["uncertified"]) == 10
    assert len(err.strip().splitlines()) == 1 and "not proved" in err
    assert all(row[kind].complete_to == 0.0 for row in res.rows for kind in res.kinds)
