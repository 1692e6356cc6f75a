"""The exit statuses of the ``mech`` command line, written once (CONTRACT.md, "Exit status").

A verdict's status comes from its conclusion (``verification.judge.Conclusion``): only a failure exits 1;
"no verdict" (nothing could be compared, e.g. one method only) is no failure and exits 0 in every command.
"""

from __future__ import annotations

__all__ = ["EXIT_OK", "EXIT_DISAGREE", "EXIT_USAGE", "EXIT_INTERNAL", "EXIT_INTERRUPTED", "internal_error"]

EXIT_OK = 0  # solved: where both methods ran they agree (or nothing could be compared)
EXIT_DISAGREE = 1  # a cross-check failed: methods disagree, a value unverified, a check case or an answer failed
EXIT_USAGE = 2  # bad usage or bad input: one line on standard error naming what was typed and what is allowed
EXIT_INTERNAL = 3  # a bug in mech, never a verdict on the physics
EXIT_INTERRUPTED = 128 + 2  # stopped by the user (SIGINT, Ctrl-C): the shells' 128 + signal number

HOW_TO_REPORT = ("this is a bug in mech, not a verdict on the physics: please report it with the command you ran "
                 "and the output of `mech --version`")


def internal_error(exc: BaseException) -> str:
    """The one line an internal error prints (after ``mech: ``): what failed and how to report it."""
    return f"internal error: {type(exc).__name__}: {exc} ({HOW_TO_REPORT})"
