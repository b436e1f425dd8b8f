"""Text -> a checked numpy function of (theta, phi): the one module that reads expressions.

Expressions (a non-uniform ``kappa``, an ``initial.shape``) are user text, so nothing here hands
text to ``eval``, sympy or any other interpreter. The text is parsed by Python's ``ast`` (which
only builds a tree, it runs nothing), every node is checked against the grammar below, and the
numpy function is then assembled from the checked tree node by node.

Grammar::

    expression := number | name | expression op expression | - expression | + expression
                | ( expression ) | function ( expression )
    op         := +  -  *  /  **
    name       := theta (polar angle, 0..pi) | phi (azimuth, 0..2 pi) | pi | e
    function   := sin | cos | tan | exp | log | sqrt | abs      (one argument)
    number     := an integer or floating-point literal, e.g. 2, 0.05, 1e-3

Limits (raise the module constants to allow more): at most ``MAX_LENGTH`` characters, nested at
most ``MAX_DEPTH`` deep (each operator, sign and call is a level; building and evaluating recurse
once per level, so keep it well below Python's recursion limit, 1000 by default); an exponent
without theta and phi (e.g. the ``9**9`` of ``9**9**9``) must lie in [-MAX_EXPONENT,
MAX_EXPONENT]. Python's parser refuses deeper parentheses (200) by itself. Values are
computed in float64, and the expression must be finite everywhere on the sphere: it is probed on
a grid that includes both poles, and checked again at every point it is evaluated on, so a
division by zero, log(0), the square root or a fractional power of a negative number, or an
overflow is refused instead of becoming inf or nan. Everything else (attributes, subscripts,
strings, keyword arguments, lambda, comprehensions, other names and functions, ...) is refused.
Every refusal is a :class:`~spectralshell.errors.ParameterError` naming the field and the text.
"""

from __future__ import annotations

import ast
import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .._validate import invalid

Function = Callable[[np.ndarray, np.ndarray], np.ndarray]

MAX_LENGTH = 1000
MAX_DEPTH = 200
MAX_EXPONENT = 64
VARIABLES = ("theta", "phi")
CONSTANTS = {"pi": math.pi, "e": math.e}
FUNCTIONS: dict[str, Callable[[np.ndarray], np.ndarray]] = {
    "sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "log": np.log, "sqrt": np.sqrt,
    "abs": np.abs}
OPERATORS: dict[type, Callable[[np.ndarray, np.ndarray], np.ndarray]] = {
    ast.Add: np.add, ast.Sub: np.subtract, ast.Mult: np.multiply, ast.Div: np.divide,
    ast.Pow: np.power}
SIGNS: dict[type, Callable[[np.ndarray], np.ndarray]] = {ast.USub: np.negative,
                                                        ast.UAdd: np.positive}
GRAMMAR = ("an expression in theta (polar) and phi (azimuth) of numbers, pi, e, + - * / **, "
           f"parentheses and {', '.join(FUNCTIONS)}")
NODE_WORDS = {ast.Attribute: "an attribute access", ast.Subscript: "a subscript",
              ast.Lambda: "a lambda", ast.Compare: "a comparison", ast.BoolOp: "and/or",
              ast.NamedExpr: "an assignment", ast.JoinedStr: "an f-string"}
# where an expression is probed when it is read: both poles, and phi over [0, 2 pi)
_PROBE = np.meshgrid(np.linspace(0.0, np.pi, 17), np.linspace(0.0, 2 * np.pi, 32, endpoint=False),
                     indexing="ij")


@dataclass(frozen=True, kw_only=True, eq=False)
class Expression:
    """A real function of (theta, phi) given as text; ``function`` evaluates it with numpy and
    raises ParameterError (naming the field) where it is not finite."""

    text: str
    function: Function


def parse_expression(name: str, text: object, *, positive: bool = False) -> Expression:
    """Read ``text`` as an expression in theta, phi (see the module docstring).

    name : the field, for messages (e.g. ``"initial.shape"``, ``"kappa"``).
    positive : also require the value to be > 0 at the probe points (e.g. a stiffness).

    Raises
    ------
    ParameterError : outside the grammar or its limits, or not finite on the sphere (or not
        positive, with ``positive``).
    """
    if not isinstance(text, str):
        raise invalid(name, text, GRAMMAR + " (given as a string)")
    node = _checked_tree(name, text)
    function = _finite(name, text, _build(name, text, node))
    values = function(*_PROBE)
    if positive and np.min(values) <= 0:
        i = np.unravel_index(np.argmin(values), values.shape)
        raise invalid(name, text, f"> 0 everywhere on the sphere ({_at(values, *_PROBE, i)})")
    return Expression(text=text, function=function)


def _checked_tree(name: str, text: str) -> ast.expr:
    """The body of the parse tree of ``text``, refused if over the length or depth limit."""
    if len(text) > MAX_LENGTH:
        raise invalid(name, text, f"{GRAMMAR}, at most {MAX_LENGTH} characters (given {len(text)})")
    try:
        with warnings.catch_warnings():     # e.g. "invalid decimal literal": no second line
            warnings.simplefilter("ignore", SyntaxWarning)
            body = ast.parse(text.strip(), mode="eval").body
    except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
        reason = exc.msg if isinstance(exc, SyntaxError) else type(exc).__name__
        raise invalid(name, text, f"{GRAMMAR} (not parseable: {reason})") from None
    stack = [(body, 1)]
    while stack:            # iterative: the depth is checked before anything recurses on it
        node, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise invalid(name, text, f"{GRAMMAR}, nested at most {MAX_DEPTH} deep")
        stack.extend((child, depth + 1) for child in ast.iter_child_nodes(node)
                     if isinstance(child, ast.expr))
    return body


def _build(name: str, text: str, node: ast.expr) -> Function:
    """The numpy function of one checked node (recursion bounded by MAX_DEPTH)."""
    if isinstance(node, ast.Constant):
        value = _number(name, text, node.value)
        return lambda theta, phi: value
    if isinstance(node, ast.Name):
        return _name(name, text, node.id)
    if isinstance(node, ast.UnaryOp) and type(node.op) in SIGNS:
        sign, operand = SIGNS[type(node.op)], _build(name, text, node.operand)
        return lambda theta, phi: sign(operand(theta, phi))
    if isinstance(node, ast.BinOp) and type(node.op) in OPERATORS:
        op, left, right = (OPERATORS[type(node.op)], _build(name, text, node.left),
                           _build(name, text, node.right))
        if isinstance(node.op, ast.Pow) and not _has_variable(node.right):
            _check_exponent(name, text, right)
        return lambda theta, phi: op(left(theta, phi), right(theta, phi))
    if (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)
            and node.func.id in FUNCTIONS and len(node.args) == 1 and not node.keywords
            and not isinstance(node.args[0], ast.Starred)):
        function, argument = FUNCTIONS[node.func.id], _build(name, text, node.args[0])
        return lambda theta, phi: function(argument(theta, phi))
    raise invalid(name, text, f"{GRAMMAR} (found {_describe(node)})")


def _number(name: str, text: str, value: object) -> np.float64:
    """A literal as float64: finite real int or float literals only (no bool, complex, str)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise invalid(name, text, f"{GRAMMAR} (found the literal {value!r})")
    try:
        number = float(value)
    except OverflowError:       # an int literal beyond float64
        number = math.inf
    if not math.isfinite(number):
        raise invalid(name, text, f"{GRAMMAR} (found a number beyond float64, |x| > 1.8e308)")
    return np.float64(number)


def _name(name: str, text: str, identifier: str) -> Function:
    """theta, phi or a constant."""
    if identifier == "theta":
        return lambda theta, phi: theta
    if identifier == "phi":
        return lambda theta, phi: phi
    if identifier in CONSTANTS:
        value = np.float64(CONSTANTS[identifier])
        return lambda theta, phi: value
    hint = f", call it as {identifier}(...)" if identifier in FUNCTIONS else ""
    raise invalid(name, text, f"{GRAMMAR} (found the name {identifier!r}{hint})")


def _has_variable(node: ast.expr) -> bool:
    """Whether theta or phi occurs in ``node``."""
    return any(isinstance(n, ast.Name) and n.id in VARIABLES for n in ast.walk(node))


def _check_exponent(name: str, text: str, exponent: Function) -> None:
    """Refuse a constant exponent outside [-MAX_EXPONENT, MAX_EXPONENT] (or not finite)."""
    with np.errstate(all="ignore"):
        value = exponent(np.float64(0.0), np.float64(0.0))
    if not abs(value) <= MAX_EXPONENT:
        raise invalid(name, text, f"{GRAMMAR}, with constant exponents in [-{MAX_EXPONENT}, "
                                  f"{MAX_EXPONENT}] (found {value:.6g})")


def _finite(name: str, text: str, function: Function) -> Function:
    """``function`` broadcast to the shape of (theta, phi), refusing values that are not finite."""
    def evaluate(theta: np.ndarray, phi: np.ndarray) -> np.ndarray:
        theta, phi = np.broadcast_arrays(np.asarray(theta, dtype=float),
                                         np.asarray(phi, dtype=float))
        with np.errstate(all="ignore"):
            values = np.broadcast_to(function(theta, phi), theta.shape).astype(float)
        bad = ~np.isfinite(values)
        if np.any(bad):
            i = np.unravel_index(np.argmax(bad), bad.shape)
            raise invalid(name, text, "finite everywhere on the sphere (division by zero, log of "
                                      "0, root or fractional power of a negative number, or "
                                      f"overflow: {_at(values, theta, phi, i)})")
        return values
    return evaluate


def _at(values: np.ndarray, theta: np.ndarray, phi: np.ndarray, i: tuple) -> str:
    """'<value> at theta = ..., phi = ...' for the point ``i``."""
    return f"{values[i]:.6g} at theta = {theta[i]:.6g}, phi = {phi[i]:.6g}"


def _describe(node: ast.AST) -> str:
    """What a refused node is, in words."""
    if isinstance(node, ast.Call):
        callee = node.func.id if isinstance(node.func, ast.Name) else None
        if callee in FUNCTIONS:
            return f"{callee} called with other than one plain argument"
        return f"a call of {callee!r}" if callee else "a call of a computed function"
    if isinstance(node, ast.BinOp):
        hint = " (write powers as **)" if isinstance(node.op, ast.BitXor) else ""
        return f"the operator {type(node.op).__name__}{hint}"
    return NODE_WORDS.get(type(node), type(node).__name__)

