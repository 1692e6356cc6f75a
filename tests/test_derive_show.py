"""`mech show ID --derive` reads as a derivation (issue 40, item 8): no line over 100 characters, text or
LaTeX, for every exercise with a declaration; and 4.12's declaration, written from its statement, gives the
equations and the normal modes the exercise states.

4.12 by hand (the bar's point at s from its upper end is at l' (sin φ, −cos φ) + s (sin ψ, −cos ψ), mass
M/l per length): T = (M/2)[l'² φ'² + l l' cos(φ−ψ) φ'ψ' + l² ψ'²/3], U = −M g (l' cos φ + (l/2) cos ψ), so
Lagrange's equations are
  M [l'² φ'' + (l l'/2)(cos(φ−ψ) ψ'' + sin(φ−ψ) ψ'²) + g l' sin φ] = 0,
  M [(l l'/2)(cos(φ−ψ) φ'' − sin(φ−ψ) φ'²) + (l²/3) ψ'' + (g l/2) sin ψ] = 0;
linearized, the mass matrix M [[l'², l l'/2], [l l'/2, l²/3]] and the stiffness M g diag(l', l/2), whose
generalized eigenvalues are the squared mode frequencies (solved here numerically, not by the formula).
"""

from __future__ import annotations

import gzip
import io
import json
import sys
from pathlib import Path

import numpy as np
import pytest

sympy = pytest.importorskip("sympy")

from mech.cli import listing  # noqa: E402
from mech.problems import physics, registry  # noqa: E402
from mech.students.points import draw  # noqa: E402

WIDTH = 100
DECLARED = [e.id for e in registry.index() if physics.why_not(registry.get(e.id)) is None]


def _printed(ex, latex, as_json=False):
    out, sys.stdout = sys.stdout, io.StringIO()
    try:
        listing.print_derivation(ex, latex=latex, as_json=as_json)
        return sys.stdout.getvalue()
    finally:
        sys.stdout = out


# What `mech show ID --derive` (text, --latex, --json) printed for every declared exercise before the
# printing path was made cheaper (a reaction's load tidied as its action's form, negated): the same text,
# byte for byte.  Where a change of a declaration or of the printing is meant to change the text,
# regenerate the file (`python tests/test_derive_show.py`) and read its diff.
PRINTED = Path(__file__).parent / "data" / "derive_show.json.gz"


def _printed_forms(ex) -> dict:
    return {"text": _printed(ex, False), "latex": _printed(ex, True), "json": _printed(ex, False, as_json=True)}


@pytest.fixture(scope="module")
def printed_before():
    with gzip.open(PRINTED, "rt", encoding="utf-8") as f:
        return json.load(f)


@pytest.mark.parametrize("ex_id", DECLARED)
def test_no_line_of_show_derive_is_over_100_characters_and_the_text_is_unchanged(ex_id, printed_before):
    ex = registry.get(ex_id)
    forms = _printed_forms(ex)
    for form in ("text", "latex"):
        text = forms[form]
        long = [(len(line), line[:60]) for line in text.splitlines() if len(line) > WIDTH]
        assert not long, (ex_id, form, long[:3])
        assert "equations of motion" in text
    assert ex_id in printed_before, f"{ex_id}: no printed text saved; regenerate {PRINTED.name}"
    for form, text in forms.items():
        assert text == printed_before[ex_id][form], (ex_id, form)


def test_long_expressions_are_wrapped_at_their_operators_and_named():
    text = _printed(registry.get("4.8"), False)  # Coulomb friction along the slip: its speed named
    assert "where" in text and "K₁ = " in text
    latex = _printed(registry.get("4.31"), True).splitlines()
    lagrangian = latex[next(i for i, line in enumerate(latex) if line.endswith(" Lagrangian L")) + 1:]
    assert lagrangian[0].startswith("L = ") and lagrangian[1].startswith("    + ")  # a sum cut between terms


def test_simplify_is_sympys_and_puts_factor_back():
    """derive_text.simplify keeps the results of sympy's pure functions (trigsimp's factor and _futrig,
    simplify itself, count_ops under each name) while sympy's simplify runs (trigsimp factors one sum many
    times over, and searches the same node again): it returns what sympy's simplify returns, and sympy has
    its own functions again after.  By hand, sin²x cos y + cos²x cos y + sin x cos x = cos y + sin(2x)/2."""
    import importlib

    from mech.problems import derive_text

    kept = [("sympy.simplify.trigsimp", "factor"), ("sympy.simplify.trigsimp", "_futrig"),
            ("sympy.simplify.simplify", "simplify"), ("sympy.simplify.simplify", "count_ops"),
            ("sympy.simplify.trigsimp", "count_ops"), ("sympy.core.function", "count_ops")]
    assert set(kept) == set(derive_text._KEPT)
    own = {(m, n): getattr(importlib.import_module(m), n) for m, n in kept}
    assert not any(getattr(f, "remembers", False) for f in own.values())
    x, y = sympy.symbols("x y", real=True)
    e = (sympy.sin(x)**2 * sympy.cos(y) + sympy.cos(x)**2 * sympy.cos(y) + sympy.sin(x) * sympy.cos(x)
         + (x**2 - y**2) / (x - y))
    got = derive_text.simplify(e)
    assert all(getattr(importlib.import_module(m), n) is f for (m, n), f in own.items())
    assert derive_text.simplify(e) == got  # again, from what the first call kept
    assert got == sympy.simplify(e)
    hand = sympy.cos(y) + sympy.sin(2 * x) / 2 + x + y
    assert all(abs(complex((got - hand).subs({x: a, y: b}).evalf(30))) < 1e-25
               for a, b in [(0.3, -1.1), (2.0, 0.7), (-0.4, 5.0)])


def test_4_12_is_declared_and_its_equations_are_lagranges_by_hand():
    ex = registry.get("4.12")
    assert ex_id_declared("4.12")
    der = ex.derive()
    phi, psi = der.d.q
    t = der.d.t
    M, l, lp, g = (der.symbol(n) for n in ("M", "l", "l_prime", "g"))
    d1, d2 = (lambda f: f.diff(t)), (lambda f: f.diff(t, 2))
    hand = [M * (lp**2 * d2(phi) + l * lp / 2 * (sympy.cos(phi - psi) * d2(psi) + sympy.sin(phi - psi) * d1(psi)**2)
                 + g * lp * sympy.sin(phi)),
            M * (l * lp / 2 * (sympy.cos(phi - psi) * d2(phi) - sympy.sin(phi - psi) * d1(phi)**2)
                 + l**2 / 3 * d2(psi) + g * l / 2 * sympy.sin(psi))]
    for derived, mine in zip(der.eom, hand):
        assert sympy.simplify(derived - mine) == 0


def ex_id_declared(ex_id):
    return ex_id in DECLARED


def test_4_12_derived_equations_linearized_give_the_stated_modes():
    """The exercise's answer (omega1 < omega2 and psi/phi of each mode) from the derived equations, linearized
    about the hanging equilibrium and solved as a generalized eigenproblem, at the defaults and at draws."""
    ex = registry.get("4.12")
    der = ex.derive()
    t = der.d.t
    q = list(der.d.q)
    acc = [qi.diff(t, 2) for qi in q]
    rest = {**{qi.diff(t, 2): 0 for qi in q}, **{qi.diff(t): 0 for qi in q}}
    rest_q = {qi: 0 for qi in q}
    eom = sympy.Matrix(der.eom)
    mass = eom.jacobian(acc).subs(rest).subs(rest_q)
    stiff = eom.subs(rest).jacobian(q).subs(rest_q)
    for p in [ex.resolve({})] + draw(ex, 4, 11):
        vals = {der.symbol(n): float(p[n]) for n in ("M", "l", "l_prime", "g")}
        Mm = np.array(mass.subs(vals), dtype=float)
        Km = np.array(stiff.subs(vals), dtype=float)
        w2, vecs = np.linalg.eig(np.linalg.solve(Mm, Km))
        order = np.argsort(w2.real)
        omegas = np.sqrt(w2.real[order])
        ratios = [vecs[1, k].real / vecs[0, k].real for k in order]
        got = ex.analytic_solver(p)
        assert omegas[0] == pytest.approx(got["omega1"], rel=1e-9)
        assert omegas[1] == pytest.approx(got["omega2"], rel=1e-9)
        assert ratios[0] == pytest.approx(got["r1"], rel=1e-8)
        assert ratios[1] == pytest.approx(got["r2"], rel=1e-8)


if __name__ == "__main__":  # regenerate the saved printed text (read its diff before committing it)
    # sympy was imported above, before stdout is swapped: it reads stdout's encoding to choose unicode
    saved = {ex_id: _printed_forms(registry.get(ex_id)) for ex_id in DECLARED}
    with gzip.GzipFile(PRINTED, "wb", mtime=0) as fh:
        fh.write(json.dumps(saved, indent=1, sort_keys=True, ensure_ascii=False).encode("utf-8"))
