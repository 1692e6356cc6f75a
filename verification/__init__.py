"""The verdict: the one judge (``judge``), the cross-check of one solve (``crosscheck``), the typed
solution it builds (``result``) and baselines (``baseline``).  It imports neither of the rooms above it:
``mech.students`` (a student's answers judged) and ``mech.studies`` (many solves)."""
