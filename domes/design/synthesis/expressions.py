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


def expression(text: str, where: str = "function"):
    """A vectorised function of ``x`` from an expression such as ``log10(x)`` or ``x**2 + 1`` (no other names)."""
    try:
        tree = ast.parse(str(text), mode="eval")
    except SyntaxError as exc:
        raise InputError(f"{where}: {text!r} is not an expression of x ({exc.msg})") from None
    for node in ast.walk(tree):
        if not isinstance(node, _NODES):
            raise InputError(f"{where}: {text!r}: {type(node).__name__} is not allowed in a function of x")
        if isinstance(node, ast.Name) and node.id != "x" and node.id not in FUNCTIONS and node.id not in CONSTANTS:
            raise InputError(f"{where}: {text!r}: unknown name {node.id!r} (use x, {', '.join(sorted(FUNCTIONS))}, "
                             "pi, e)")
        if isinstance(node, ast.Call) and not (isinstance(node.func, ast.Name) and node.func.id in FUNCTIONS):
            raise InputError(f"{where}: {text!r}: only the functions {', '.join(sorted(FUNCTIONS))} may be called")
        if isinstance(node, ast.Constant) and not isinstance(node.value, (int, float)):
            raise InputError(f"{where}: {text!r}: only numbers may appear as constants")
    code = compile(tree, where, "eval")
    names = {"__builtins__": {}, **FUNCTIONS, **CONSTANTS}

    def f(x):
        with np.errstate(all="ignore"):
            return eval(code, names, {"x": np.asarray(x, dtype=float)})  # noqa: S307 - AST checked above

    f.text = str(text)
    return f
