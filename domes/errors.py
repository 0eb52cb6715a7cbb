"""Errors raised by DOMES-py.

Every error says what was wrong and, where it helps, what to do instead.
The command-line interface prints the message and exits with status 2.
"""


class DomesError(ValueError):
    """Bad input to DOMES-py: the message says what and where.

    >>> raise DomesError("links must be >= 2, got 1")
    Traceback (most recent call last):
    ...
    domes.errors.DomesError: links must be >= 2, got 1
    """
