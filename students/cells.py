"""A student's cell: the state of one expected value, decided once and read by every report.

``right``, ``wrong``, ``invalid`` (the answer could not be read, or the assignment forbids what the
file set), ``unanswered`` (left empty) or ``not-graded`` (mech reached no verdict: the command's budget
ran out, mech failed); every state but right and wrong carries its reason.  The table, ``--json``,
JUnit and the gradebook map it to words, elements and cells in one place each.
"""

from __future__ import annotations

import enum

__all__ = ["State"]


class State(enum.Enum):
    RIGHT = "right"
    WRONG = "wrong"
    INVALID = "invalid"
    UNANSWERED = "unanswered"
    NOT_GRADED = "not-graded"

    @property
    def needs_review(self) -> bool:
        """A cell a person must look at (the gradebook's ``review`` count)."""
        return self in (State.INVALID, State.NOT_GRADED)
