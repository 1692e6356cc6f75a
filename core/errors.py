"""The two ways a solve refuses, importable without the rest of mech (``import mech`` and ``mech --help``
load this module alone)."""


class BadInput(ValueError):
    """A parameter value the exercise cannot take; the message is one line for the user.

    ``BadInput(reason, field="theta0", kind="range")``: the message is ``"theta0: <reason>"``; ``field``
    (the parameter, output or option refused), ``kind`` (what is wrong with it: "range", "unit",
    "syntax", "unknown", ...) and ``reason`` (the message without the field) are there for a caller that
    words the refusal its own way, so that no caller rewrites or parses a message."""

    def __init__(self, message: str = "", *, field: str | None = None, kind: str | None = None):
        self.field, self.kind, self.reason = field, kind, str(message)
        super().__init__(f"{field}: {message}" if field else str(message))


class NumericFailure(RuntimeError):
    """The numeric solver could not produce a trustworthy answer; never swallowed into a number."""


class BadUsage(Exception):
    """A request that cannot be carried out as asked (an optional package missing, a file it cannot write);
    the message is one line for the user, and the command line exits 2 on it."""
