"""Scalar fields and conditions written as expressions of the coordinates x, y (mm), and z on
a surface in space.

A scene gives a course direction, a stitch value or a region's extent as text such as
`"45 + 10 * sin(pi * x / 200)"` or `"abs(y - 100) < 30"`. The text is parsed once, checked to
use only the coordinates, numbers, arithmetic, comparisons and the functions of `FUNCTIONS`,
and evaluated with NumPy on arrays of points (cell centres). No DOLFINx: the scene reader
checks expressions before anything runs. `piecewise_linear` writes the field that is linear
between values at stations along one coordinate (a designed stitch field).
"""

import ast
from dataclasses import dataclass

import numpy as np

from rve_rod.errors import InputError

__all__ = [
    "CONSTANTS",
    "FUNCTIONS",
    "PLANE",
    "SPACE",
    "FieldExpression",
    "expression_coordinates",
    "piecewise_linear",
]

PLANE = ("x", "y")
"""The coordinates of an expression on a plane part."""
SPACE = ("x", "y", "z")
"""The coordinates of an expression on a part in space (a flat one has z = 0)."""


def expression_coordinates(in_space: bool) -> tuple[str, ...]:
    """The coordinates a part's expressions may use: SPACE in space, else PLANE."""
    return SPACE if in_space else PLANE


FUNCTIONS = {
    "sin": np.sin,
    "cos": np.cos,
    "tan": np.tan,
    "arctan2": np.arctan2,
    "sqrt": np.sqrt,
    "exp": np.exp,
    "log": np.log,
    "abs": np.abs,
    "minimum": np.minimum,
    "maximum": np.maximum,
    "where": np.where,
    "clip": np.clip,
}
"""Functions an expression may call (NumPy's, elementwise)."""

CONSTANTS = {"pi": np.pi}

_NODES = (
    ast.Expression,
    ast.BinOp,
    ast.UnaryOp,
    ast.Compare,
    ast.BoolOp,
    ast.Call,
    ast.Name,
    ast.Load,
    ast.Constant,
    ast.operator,
    ast.unaryop,
    ast.cmpop,
    ast.boolop,
)


@dataclass(frozen=True)
class FieldExpression:
    """An expression of x, y (mm), checked on construction (InputError naming `key`).

    Attributes:
        text: the expression, Python syntax (`**` for powers, `and`/`or` in conditions).
        key: the scene key it comes from (for messages).
        coordinates: the coordinates it may use: ("x", "y"), or ("x", "y", "z") for a field
            on a surface in space.
    """

    text: str
    key: str = "expression"
    coordinates: tuple[str, ...] = PLANE

    def __post_init__(self):
        try:
            tree = ast.parse(self.text, mode="eval")
        except SyntaxError as error:
            raise InputError(
                f"{self.key}: {self.text!r} is not an expression ({error.msg})"
            ) from None
        allowed = {*self.coordinates, *FUNCTIONS, *CONSTANTS}
        for node in ast.walk(tree):
            if not isinstance(node, _NODES):
                raise InputError(
                    f"{self.key}: {self.text!r} uses {type(node).__name__}; only numbers, x, y, "
                    f"arithmetic, comparisons and {', '.join(FUNCTIONS)} are allowed"
                )
            if isinstance(node, ast.Name) and node.id not in allowed:
                raise InputError(
                    f"{self.key}: {self.text!r} uses the unknown name {node.id!r} "
                    f"(valid: {', '.join(self.coordinates)}, pi, {', '.join(FUNCTIONS)})"
                )
            if isinstance(node, ast.Call) and not (
                isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS
            ):
                called = node.func.id if isinstance(node.func, ast.Name) else "an expression"
                raise InputError(
                    f"{self.key}: {self.text!r} calls the unknown function {called!r} "
                    f"(valid: {', '.join(FUNCTIONS)})"
                )
            if isinstance(node, ast.Constant) and not isinstance(node.value, int | float):
                raise InputError(f"{self.key}: {self.text!r} holds a non-number {node.value!r}")

    @property
    def is_condition(self) -> bool:
        """Whether the expression is a condition (a comparison, `and`, `or`): true or false
        at each point, 1 or 0 as a value."""
        body = ast.parse(self.text, mode="eval").body
        return isinstance(body, ast.Compare | ast.BoolOp)

    def as_value(self, what: str) -> "FieldExpression":
        """Itself, or InputError when it is a condition where `what` (e.g. "a course
        direction in degrees") is wanted (`"x > 25"` gave angles of 0 and 1 degree)."""
        if self.is_condition:
            raise InputError(
                f"{self.key}: {self.text!r} is a condition (true or false), not {what}; "
                "choose between values with where(condition, value, other value)"
            )
        return self

    def as_condition(self) -> "FieldExpression":
        """Itself, or InputError when it is a value, not a condition (`"x + 5"` selected
        every cell where it is not 0)."""
        if not self.is_condition:
            raise InputError(
                f"{self.key}: {self.text!r} is a value, not a condition; write a comparison "
                "such as 'x > 25' or 'abs(y - 100) < 20 and x < 50'"
            )
        return self

    def __call__(self, x: np.ndarray, y: np.ndarray, z: np.ndarray | None = None) -> np.ndarray:
        """Values (float array, the shape of x) at the points (x, y[, z]) in mm (z = 0 when
        not given)."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        z = np.zeros_like(x) if z is None else np.asarray(z, dtype=float)
        tree = ast.parse(self.text, mode="eval")
        # `and`/`or` of arrays: elementwise
        tree = _ElementwiseLogic().visit(tree)
        code = compile(ast.fix_missing_locations(tree), self.key, "eval")
        names = {"x": x, "y": y, "z": z, **FUNCTIONS, **CONSTANTS, "_all": np.logical_and.reduce}
        names["_any"] = np.logical_or.reduce
        with np.errstate(all="ignore"):
            value = eval(code, {"__builtins__": {}}, names)  # the names were checked above
        value = np.broadcast_to(np.asarray(value, dtype=float), x.shape).copy()
        if not np.all(np.isfinite(value)):
            raise InputError(f"{self.key}: {self.text!r} is not finite at some points")
        return value


def piecewise_linear(coordinate: str, stations, values) -> str:
    """The expression of the field equal to `values` at `stations` (increasing, mm) along
    `coordinate` ("x", "y" or "z"), linear between them and constant beyond:
    v_0 + sum_i (v_i+1 - v_i) clip((coordinate - t_i) / (t_i+1 - t_i), 0, 1)."""
    terms = [repr(float(values[0]))]
    for i in range(len(stations) - 1):
        rise = float(values[i + 1]) - float(values[i])
        span = float(stations[i + 1]) - float(stations[i])
        start = float(stations[i])
        terms.append(f"{rise!r} * clip(({coordinate} - {start!r}) / {span!r}, 0.0, 1.0)")
    return " + ".join(terms)


class _ElementwiseLogic(ast.NodeTransformer):
    """`a and b` -> `_all([a, b])`, `a or b` -> `_any([a, b])`; chained comparisons too."""

    def visit_BoolOp(self, node):
        self.generic_visit(node)
        name = "_all" if isinstance(node.op, ast.And) else "_any"
        return ast.Call(ast.Name(name, ast.Load()), [ast.List(node.values, ast.Load())], [])

    def visit_Compare(self, node):
        self.generic_visit(node)
        if len(node.ops) == 1:
            return node
        parts = []
        left = node.left
        for op, right in zip(node.ops, node.comparators, strict=True):
            parts.append(ast.Compare(left, [op], [right]))
            left = right
        return ast.Call(ast.Name("_all", ast.Load()), [ast.List(parts, ast.Load())], [])
