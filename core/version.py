"""The installed distribution's version (``mech.__version__``, the key of ``mech assign``), read when asked."""

from __future__ import annotations

DISTRIBUTION = "mech-likharev"


def version() -> str:
    """The version pip installed, or "unknown" when mech runs from files that were never installed."""
    from importlib.metadata import PackageNotFoundError
    from importlib.metadata import version as installed

    try:
        return installed(DISTRIBUTION)
    except PackageNotFoundError:
        return "unknown"
