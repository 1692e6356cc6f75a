"""The two ways a solve refuses, importable without the rest of mech (``import mech`` and ``mech --help``
load this module alone)."""


class BadInput(ValueError):
    """A parameter value the exercise cannot take; the message is one line for the user."""


class NumericFailure(RuntimeError):
    """The numeric solver could not produce a trustworthy answer; never swallowed into a number."""


class BadUsage(Exception):
    """A request that cannot be carried out as asked (an optional package missing, a file it cannot write);
    the message is one line for the user, and the command line exits 2 on it."""
