"""Expression fields (a non-uniform kappa, initial.shape) are user text: only arithmetic in theta
and phi is accepted (spectralshell/params/expression.py), everything else is a one-line
ParameterError (exit status 2 on the command line), and nothing in the text is ever run.

Hostile strings carry a sentinel: if any part of them were executed, a file would appear.
Valid expressions are random trees of the grammar, compared with an independent evaluation of the
same tree by Python's math module, point by point.
"""

from __future__ import annotations

import ast
import math
import os
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

import spectralshell
import spectralshell as ss
from spectralshell.cli import main
from spectralshell.errors import ParameterError
from spectralshell.params import expression
from spectralshell.params.expression import MAX_DEPTH, MAX_LENGTH, parse_expression

SENTINEL = Path(tempfile.gettempdir()) / f"spectralshell-pwned-{os.getpid()}"
TOUCH = f"open({str(SENTINEL)!r}, 'w')"
SYSTEM = f"__import__('os').system('touch {SENTINEL}')"

# code that would run something or read something if it were evaluated, and other syntax
CODE = [
    SYSTEM, TOUCH, f"exec({TOUCH!r})", f"eval({TOUCH!r})", f"compile({TOUCH!r}, '', 'eval')",
    "__import__('os')", "import os", "from os import system",
    "theta.__class__", "theta.__class__.__mro__[1].__subclasses__()", "().__class__.__bases__",
    "sin.__globals__", "phi.real", "(1).__add__(2)", "pi.__doc__",
    f"(lambda: {TOUCH})()", "lambda theta: theta",
    "[x for x in (1, 2)]", f"[{TOUCH} for _ in 'a']", "{x: 1 for x in 'ab'}", "(x for x in ())",
    "{1, 2}", "{'a': 1}", "[theta]", "(theta, phi)",
    "f'{theta}'", f"f'{{{TOUCH}}}'", "'theta'", "b'theta'", "theta + 'x'", "...",
    "(x := 1)", "sin(x=theta)", "sin(*[theta])", "sin(**{})", "sin()", "sin(theta, phi)",
    "theta[0]", "theta[::2]", "theta if phi else 1", "theta < phi", "theta and phi",
    "not theta", "~1", "theta // 2", "theta % 2", "theta @ phi", "theta << 2", "theta ^ 2",
    "theta | 1", "1j", "2 + 3j", "True", "None", "nan", "inf", "x", "Theta", "sinh(theta)",
    "foo(theta)", "getattr(theta, 'x')", "S('1')", "sympify('1')", "Symbol('x')", "Integer(2)",
    "open", "sin", "print(1)", "await theta", "yield theta", "theta; phi", "theta = 1",
    "θ", "sin(θ)", "théta", "\u0441os(theta)", "theta\u200b", "\ufefftheta",
    "theta\x00", "\x00",
]
# refused on their own (inside parentheses a line break is harmless, and a term that is not
# finite can be cancelled, as in 1/(2 + 1/0)): line breaks, sizes beyond the limits, values
# that are not finite
MALFORMED = [
    "theta\n+phi", "theta\r\nphi",
    "9**9**9", "2**10**10", "theta**1000", "10**(10**10)", "(-2)**99", "theta**(1/0)",
    "1e999", "-1e999", "1" * 400, "9" * 999,
    "1/0", "log(0)", "sqrt(-1)", "(-8)**(1/3)", "log(-1)", "1/sin(theta)", "log(sin(theta))",
    "exp(1000)", "tan(pi/2)**400", "0/0", "theta/theta", "1/(phi*0)",
    "\n\n", "", "   ", "#",
    "(" * 10_000 + "theta" + ")" * 10_000, "(" * 300 + "theta" + ")" * 300,
    "-" * 999 + "theta", "+" * 999 + "1", "sin(" * 250 + "theta" + ")" * 250,
    "+".join(["1"] * 300), "theta" + " " * 2000,
]
HOSTILE = CODE + MALFORMED
FUNCTIONS = sorted(expression.FUNCTIONS)


def _refused(name: str, text: str) -> str:
    """The message of the ParameterError that ``text`` must raise; checks no side effect."""
    with pytest.raises(ParameterError) as info:
        parse_expression(name, text)
    assert not SENTINEL.exists()
    return str(info.value)


@pytest.mark.parametrize("text", HOSTILE)
def test_hostile_strings_are_refused_on_one_line(text):
    message = _refused("initial.shape", text)
    assert message.startswith("initial.shape = ") and "is invalid: must be" in message
    assert "\n" not in message and len(message) < 700


# hostile fragments spliced into legitimate expressions, and arbitrary text
_valid_context = st.sampled_from(["{}", "sin({})", "0.1*{} + cos(theta)", "({})**2",
                                  "theta*({})", "exp(-{})", "1/(2 + {})"])


@settings(max_examples=200, deadline=None)
@given(_valid_context, st.sampled_from(CODE))
def test_code_inside_valid_expressions_is_refused(context, fragment):
    _refused("kappa", context.format(fragment))


@settings(max_examples=300, deadline=None)
@given(st.text(alphabet=st.characters(codec="utf-8"), max_size=200)
       | st.text(alphabet="thetaphisincoexplgrqb_.()[]{}:=,*/+-~<>!'\"0123456789 \n\x00",
                 max_size=200))
def test_arbitrary_text_is_accepted_or_refused_with_parameter_error(text):
    """Any text whatsoever: an expression or a ParameterError, never another exception."""
    try:
        parse_expression("initial.shape", text)
    except ParameterError as exc:
        assert "\n" not in str(exc)
    assert not SENTINEL.exists()


def test_non_strings_are_refused():
    for value in (None, 1.5, b"theta", ["theta"], {"theta": 1}):
        with pytest.raises(ParameterError, match="given as a string"):
            parse_expression("initial.shape", value)


def test_limits_are_what_the_messages_say():
    assert "at most 1000 characters (given 1001)" in _refused("kappa", "1" + "+0" * 500)
    assert f"nested at most {MAX_DEPTH} deep" in _refused("kappa", "-" * MAX_DEPTH + "theta")
    parse_expression("kappa", "-" * (MAX_DEPTH - 1) + "theta")
    assert "constant exponents in [-64, 64] (found 65)" in _refused("kappa", "theta**(60 + 5)")
    parse_expression("kappa", "(1 + theta)**-64")
    text = "theta + " * 200 + "phi"
    assert f"... ({len(text) + 2} characters)" in _refused("initial.shape", text)  # cut short


def test_a_raised_length_limit_still_refuses_what_cannot_be_built(monkeypatch):
    """With MAX_LENGTH raised, nesting beyond the parser's own limits (parentheses, its
    recursion and memory) or MAX_DEPTH is still a ParameterError, not a RecursionError or
    MemoryError."""
    monkeypatch.setattr(expression, "MAX_LENGTH", 10**7)
    for text in ("(" * 100_000 + "1" + ")" * 100_000, "-" * 1_000_000 + "1", "-" * 5000 + "1",
                 "-" * 2000 + "1", "sin(" * 100_000 + "1" + ")" * 100_000):
        _refused("kappa", text)


def test_values_are_checked_wherever_they_are_evaluated():
    """Probed on a grid with both poles when read, and checked again at every evaluation."""
    assert "inf at theta = 0, phi = 0" in _refused("initial.shape", "1/0")
    assert "at theta = 3.14159" in _refused("initial.shape", "log(1 + cos(theta))")
    f = parse_expression("initial.shape", "1/(theta - 0.5)").function   # 0.5: not a probe point
    assert f(np.array([0.4, 0.6]), 0.0) == pytest.approx([-10.0, 10.0])
    with pytest.raises(ParameterError, match=r"initial.shape = '1/\(theta - 0.5\)' .* inf at "
                                             r"theta = 0.5, phi = 1"):
        f(np.array([0.4, 0.5]), 1.0)


def test_kappa_must_be_positive_everywhere():
    with pytest.raises(ParameterError, match=r"kappa = '0.06\*cos\(theta\)' is invalid: must be "
                                             r"> 0 everywhere on the sphere \(-0.06 at theta = "
                                             r"3.14159"):
        ss.simulate({"params": {"kappa": "0.06*cos(theta)", "nu": 0.01},
                     "initial": {"shape": "2:0"}, "simulate": {"t_end": 1}})
    parse_expression("kappa", "0.06*(1.5 + cos(theta))", positive=True)


def test_constant_and_legitimate_expressions_evaluate_on_the_grid_shape():
    f = parse_expression("kappa", "0.5").function
    theta, phi = np.meshgrid(np.linspace(0, np.pi, 3), np.linspace(0, 6, 4), indexing="ij")
    values = f(theta, phi)
    assert values.shape == (3, 4) and values.flags.writeable and np.all(values == 0.5)
    g = parse_expression("initial.shape", " 0.05*sin(theta)**2*cos(2*phi) + e**-1*abs(tan(phi)) "
                                          "- sqrt(pi)*log(2)/exp(1) + +1e-3 - -2").function
    want = (0.05 * np.sin(theta) ** 2 * np.cos(2 * phi) + np.abs(np.tan(phi)) / np.e
            - np.sqrt(np.pi) * np.log(2) / np.e + 1e-3 + 2)
    assert np.max(np.abs(g(theta, phi) - want)) < 1e-15


# ----------------------------------------------------------------------------- valid trees
# A tree is (text, reference): reference(theta, phi) evaluates it with the math module and
# returns (value, largest |intermediate|), which scales the rounding tolerance.
def _leaf():
    numbers = (st.integers(-9, 9).map(lambda n: (str(n), n))
               | st.floats(-10, 10, allow_nan=False).map(lambda x: round(x, 4))
                 .map(lambda x: (repr(x), x)))
    return (numbers.map(lambda p: (f"({p[0]})", lambda th, ph, v=float(p[1]): (v, abs(v))))
            | st.sampled_from([("theta", lambda th, ph: (th, abs(th))),
                               ("phi", lambda th, ph: (ph, abs(ph))),
                               ("pi", lambda th, ph: (math.pi, math.pi)),
                               ("e", lambda th, ph: (math.e, math.e))]))


# unary forms that are finite for every finite argument: (text template, math function)
UNARY = [("-({})", lambda x: -x), ("+({})", lambda x: x), ("sin({})", math.sin),
         ("cos({})", math.cos), ("tan(sin({}))", lambda x: math.tan(math.sin(x))),
         ("exp(cos({}))", lambda x: math.exp(math.cos(x))), ("abs({})", abs),
         ("log(1 + ({})**2)", lambda x: math.log(1 + x ** 2)),
         ("sqrt(abs({}))", lambda x: math.sqrt(abs(x))), ("({})**3", lambda x: x ** 3),
         ("(1 + abs({}))**-1.5", lambda x: (1 + abs(x)) ** -1.5)]
BINARY = [("({}) + ({})", lambda a, b: a + b), ("({}) - ({})", lambda a, b: a - b),
          ("({}) * ({})", lambda a, b: a * b), ("({}) / (2 + sin({}))", lambda a, b: a / (2 + math.sin(b))),
          ("(1 + abs({}))**cos({})", lambda a, b: (1 + abs(a)) ** math.cos(b))]


def _unary(pair):
    (template, fn), (text, ref) = pair

    def reference(th, ph):
        x, size = ref(th, ph)
        y = fn(x)
        return y, max(size, abs(y))
    return template.format(text), reference


def _binary(triple):
    (template, fn), (ta, ra), (tb, rb) = triple

    def reference(th, ph):
        (a, sa), (b, sb) = ra(th, ph), rb(th, ph)
        y = fn(a, b)
        return y, max(sa, sb, abs(y))
    return template.format(ta, tb), reference


_valid = st.recursive(_leaf(), lambda sub: (
    st.tuples(st.sampled_from(UNARY), sub).map(_unary)
    | st.tuples(st.sampled_from(BINARY), sub, sub).map(_binary)), max_leaves=12)
_POINTS = [(0.0, 0.0), (np.pi, 1.0), (0.3, 2.5), (1.2, 6.0), (np.pi / 2, 3.3), (2.9, 0.7)]


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_valid)
def test_valid_expressions_are_accepted_and_agree_with_an_independent_evaluation(tree):
    text, reference = tree
    assume(len(text) <= MAX_LENGTH)
    expected = [reference(th, ph) for th, ph in _POINTS]
    assume(all(abs(v) < 1e200 for v, _ in expected))
    f = parse_expression("initial.shape", text).function
    theta, phi = np.array(_POINTS).T
    got = f(theta, phi)
    assert got.shape == theta.shape and np.all(np.isfinite(got))
    for g, (want, size) in zip(got, expected):
        assert abs(g - want) <= 1e-9 * max(1.0, size), (text, g, want)


# ----------------------------------------------------------------------------- command line
def test_the_issue_command_exits_2_and_runs_nothing(tmp_path):
    """The command of issue 23, in a fresh process and a scratch directory."""
    env = {**os.environ, "PYTHONPATH": str(Path(spectralshell.__file__).parent.parent)}
    done = subprocess.run([sys.executable, "-m", "spectralshell", "simulate", "sphere", "--shape",
                           "__import__('os').system('touch pwned')", "--kappa", "0.06", "--nu",
                           "0.002", "--t-end", "1"], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 2 and done.stdout == ""
    assert done.stderr.count("\n") == 1 and done.stderr.startswith("spectralshell: error: "
                                                                   "initial.shape = ")
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("flag, text", [("--shape", "1/0"), ("--shape", "log(0)"),
                                        ("--shape", "sqrt(-1)"), ("--shape", SYSTEM),
                                        ("--kappa", SYSTEM), ("--kappa", "log(0)"),
                                        ("--kappa", "-0.06 + 0*theta")])
def test_cli_expression_flags_exit_2_with_one_line(flag, text, capsys, monkeypatch, tmp_path):
    monkeypatch.chdir(tmp_path)
    args = {"--shape": "2:0", "--kappa": "0.06", flag: text}
    argv = ["simulate", "sphere", f"--shape={args['--shape']}", f"--kappa={args['--kappa']}",
            "--nu", "0.002", "--t-end", "1"]
    assert main(argv) == 2
    err = capsys.readouterr().err
    field = "initial.shape" if flag == "--shape" else "kappa"
    assert err.count("\n") == 1 and err.startswith(f"spectralshell: error: {field} = ")
    assert list(tmp_path.iterdir()) == [] and not SENTINEL.exists()


def test_text_that_makes_the_parser_warn_still_gives_one_line():
    """Python's parser warns about e.g. '1and' or '1(theta)' (a second line on stderr): the
    warnings are dropped, the text refused."""
    for text in ("1and theta", "1(theta)", "theta is 1"):
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            _refused("initial.shape", text)
        assert caught == [], text


def test_scene_file_with_a_hostile_kappa_exits_2(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    scene = tmp_path / "evil.toml"
    scene.write_text(f'model = "sphere"\n[params]\nkappa = {SYSTEM!r}\nnu = 0.002\n'
                     f'[initial]\nshape = "2:0"\n[simulate]\nt_end = 1\n'
                     f'[output]\ndir = "{tmp_path / "out"}"\n')
    assert main(["simulate", str(scene)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("spectralshell: error: kappa = ")
    assert [p.name for p in tmp_path.iterdir()] == ["evil.toml"] and not SENTINEL.exists()


# ----------------------------------------------------------------------------- one owner
FORBIDDEN_CALLS = {"eval", "exec", "compile", "__import__", "parse_expr", "sympify", "S",
                   "lambdify", "literal_eval"}


def test_no_module_of_the_package_interprets_text():
    """Nothing in spectralshell calls an interpreter of text (eval, exec, compile, sympy's
    parse_expr / sympify / S / lambdify) or imports sympy, so no other path can reopen the hole:
    expressions are read only by params/expression.py, which builds numpy functions itself."""
    root = Path(spectralshell.__file__).parent
    found = []
    for path in root.rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.Call):
                func = node.func
                called = func.id if isinstance(func, ast.Name) else getattr(func, "attr", None)
                bare_or_sympy = isinstance(func, ast.Name) or called != "compile"   # re.compile
                if called in FORBIDDEN_CALLS and bare_or_sympy:
                    found.append(f"{path.relative_to(root)}:{node.lineno} calls {called}")
            elif isinstance(node, (ast.Import, ast.ImportFrom)):
                names = [a.name for a in node.names] + [getattr(node, "module", None) or ""]
                if any(n.split(".")[0] == "sympy" for n in names):
                    found.append(f"{path.relative_to(root)}:{node.lineno} imports sympy")
    assert not found, found
