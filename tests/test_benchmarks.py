"""Every benchmark still imports and parses its options (the benchmarks themselves are run by hand).

All of them start in one fresh interpreter, one after the other (``runpy``, as ``python bench_X.py --help``
would), so that the interpreter and the imports they share start once; each one's exit and usage text is
reported by name.
"""

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCRIPTS = sorted((ROOT / "benchmarks").glob("bench_*.py"))

RUN_ALL = """
import contextlib, io, json, os, runpy, sys
results, path = {}, list(sys.path)
for script in sys.argv[1:]:
    out, err = io.StringIO(), io.StringIO()
    sys.argv = [script, "--help"]
    sys.path[:] = [os.path.dirname(script), *path]     # as `python script` puts the script's folder first
    code = 0
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            runpy.run_path(script, run_name="__main__")
        except SystemExit as stop:
            code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
        except BaseException as exc:
            code, err = 1, io.StringIO(f"{type(exc).__name__}: {exc}")
    results[script] = [code, out.getvalue(), err.getvalue()]
sys.__stdout__.write(json.dumps(results))
"""


def test_every_benchmark_starts():
    proc = subprocess.run([sys.executable, "-c", RUN_ALL, *map(str, SCRIPTS)], cwd=ROOT, capture_output=True,
                          text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    results = json.loads(proc.stdout)
    assert sorted(results) == sorted(map(str, SCRIPTS)) and len(SCRIPTS) > 10
    for script, (code, out, err) in results.items():
        assert code == 0, (Path(script).name, err[-3000:])
        assert "usage:" in out, (Path(script).name, out[-1000:], err[-1000:])
