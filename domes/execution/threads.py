"""How many threads the numerical libraries (BLAS, LAPACK, OpenMP) may use: one place for every command.

NumPy's and SciPy's linear algebra starts a thread per core by default. On
a machine that is busy with other work, or where DOMES-py already runs one
process per core (``--workers``), those threads compete for the same cores
and a fit that takes a second can take minutes. Every command therefore
runs under :func:`limited_threads`: one thread unless the environment
variable ``DOMES_THREADS`` says otherwise (a whole number, or ``all`` for
the libraries' own default). Dask's workers get one thread each from Dask.

>>> with limited_threads(1) as n:
...     n
1
"""

from __future__ import annotations

import os
from contextlib import contextmanager

from domes.errors import InputError

#: The environment variable that sets the thread limit.
THREADS_VARIABLE = "DOMES_THREADS"


def thread_limit() -> int | None:
    """The limit from ``DOMES_THREADS`` (default 1; None for ``all``: the libraries' own default)."""
    text = os.environ.get(THREADS_VARIABLE, "").strip().lower()
    if not text:
        return 1
    if text == "all":
        return None
    if not text.isdigit() or int(text) < 1:
        raise InputError(f"{THREADS_VARIABLE} must be a whole number of at least 1, or 'all'; got {text!r}")
    return int(text)


#: The environment variables by which the numerical libraries (OpenBLAS, MKL, BLIS, OpenMP) size their thread
#: pools as they load.
THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "OMP_NUM_THREADS")


@contextmanager
def limited_threads(limit: int | None | str = "env"):
    """Run the body with the numerical libraries' thread pools limited to ``limit`` threads (``"env"``: from
    :func:`thread_limit`; None: not limited). Yields the limit in force.

    The libraries already loaded are limited by threadpoolctl; those the body loads itself (a command imports
    its numerical modules when it runs) read the limit from the environment as they load, so it is put there
    for the body's time too.
    """
    from threadpoolctl import threadpool_limits

    if limit == "env":
        limit = thread_limit()
    if limit is None:
        yield None
        return
    saved = {name: os.environ.get(name) for name in THREAD_VARIABLES}
    os.environ.update(dict.fromkeys(THREAD_VARIABLES, str(limit)))
    try:
        with threadpool_limits(limits=limit):
            yield limit
    finally:
        for name, value in saved.items():
            if value is None:
                os.environ.pop(name, None)
            else:
                os.environ[name] = value
