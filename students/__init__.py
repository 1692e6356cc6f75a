"""A student's answers: numbers and formulas parsed (``formula_ast``), the points a formula is held at
(``points``), mech's reference (``reference``), hints (``explain``), a formula's verdict (``formulas``),
the verdicts of ``--expect`` (``answers``), one expected value read (``expectations``), answers files
(``answers_files``), the class run (``classrun``), the gradebook and reports (``gradebook``) and personal variants
(``assign``).  Above ``mech.studies`` and ``mech.verification``; every verdict comes from
``mech.verification.judge``."""
