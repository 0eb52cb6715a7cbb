"""Functions of ``x`` written as text in task files: ``log10(x)``, ``3.1 - 2.4*x``, checked before use.

>>> f = expression("x**2 + 1")
>>> float(f(2.0))
5.0
"""

from __future__ import annotations

import ast
import math

import numpy as np

from domes.errors import InputError

#: Names an expression of ``x`` may use.
FUNCTIONS = {"sin": np.sin, "cos": np.cos, "tan": np.tan, "exp": np.exp, "log": np.log, "log10": np.log10,
             "sqrt": np.sqrt, "abs": np.abs, "arctan": np.arctan, "sinh": np.sinh, "cosh": np.cosh, "tanh": np.tanh}
CONSTANTS = {"pi": math.pi, "e": math.e}
_NODES = (ast.Expression, ast.BinOp, ast.UnaryOp, ast.Call, ast.Name, ast.Constant, ast.Load, ast.Add, ast.Sub,
          ast.Mult, ast.Div, ast.Pow, ast.USub, ast.UAdd)


#: The longest expression taken (a function of a task file is a line, not a program).
MAX_LENGTH = 1000


class _Floats(ast.NodeTransformer):
    """Every number becomes a float64, so that powers overflow to inf at once (``9**9**9`` as integers would
    run for hours)."""

    def visit_Constant(self, node):
        try:
            value = float(node.value)
        except OverflowError:
            raise InputError(f"the number {str(node.value)[:20]}... is too large for a float") from None
        return ast.copy_location(ast.Call(ast.Name("_float", ast.Load()), [ast.Constant(value)], []), node)


def expression(text: str, where: str = "function"):
    """A vectorised function of ``x`` from an expression such as ``log10(x)`` or ``x**2 + 1`` (no other names).

    Arithmetic is in floats: a power too large gives inf, never a long wait.

    >>> float(expression("0*9**9**9 + x")(1.0))
    nan
    """
    shown = str(text) if len(str(text)) <= 60 else str(text)[:60] + "..."
    if len(str(text)) > MAX_LENGTH:
        raise InputError(f"{where}: {shown!r} is {len(str(text))} characters long; at most {MAX_LENGTH}")
    try:
        tree = ast.parse(str(text), mode="eval")
    except SyntaxError as exc:
        raise InputError(f"{where}: {shown!r} is not an expression of x ({exc.msg})") from None
    except (RecursionError, MemoryError):
        raise InputError(f"{where}: {shown!r} is nested too deeply") from None
    for node in ast.walk(tree):
        if not isinstance(node, _NODES):
            raise InputError(f"{where}: {shown!r}: {type(node).__name__} is not allowed in a function of x")
        if isinstance(node, ast.Name) and node.id != "x" and node.id not in FUNCTIONS and node.id not in CONSTANTS:
            raise InputError(f"{where}: {shown!r}: unknown name {node.id!r} (use x, {', '.join(sorted(FUNCTIONS))}, "
                             "pi, e)")
        if isinstance(node, ast.Call) and not (isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS):
            raise InputError(f"{where}: {shown!r}: only the functions {', '.join(sorted(FUNCTIONS))} may be called")
        if isinstance(node, ast.Constant) and not isinstance(node.value, (int, float)):
            raise InputError(f"{where}: {shown!r}: only numbers may appear as constants")
    try:
        tree = ast.fix_missing_locations(_Floats().visit(tree))
    except InputError as exc:
        raise InputError(f"{where}: {shown!r}: {exc}") from None
    code = compile(tree, where, "eval")
    names = {"__builtins__": {}, "_float": np.float64, **FUNCTIONS, **CONSTANTS}

    def f(x):
        x = np.asarray(x, dtype=float)
        with np.errstate(all="ignore"):                  # a constant (``2**2**2**2**2``) gets the shape of x too
            return eval(code, names, {"x": x}) + np.zeros_like(x)  # noqa: S307 - AST checked above

    f.text = str(text)
    return f
