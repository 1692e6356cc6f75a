"""The derived equations as a student reads them: simplified, wrapped at their operators, no line over
``WIDTH`` characters (``mech show ID --derive``, text and LaTeX).

An expression is simplified where that is quick (the sin² + cos² of a turned frame taken out of 4.31's
Lagrangian; ``simplify`` where it is small, else its common factors taken out). A sum too wide
for a line is cut between its terms, each line after the first opening with its sign; a term too wide
alone has its widest part named (``K₁``, ``K₂``, ... as common subexpressions are), defined on the lines
after it (``where K₁ = ...``). LaTeX is cut the same way, at the top-level ``+`` and ``-`` (then at any
space: a line break in LaTeX source is a space). Imported by ``physics`` only where sympy is.
"""

from __future__ import annotations

import importlib
import textwrap

import sympy as sp
from sympy.core.function import AppliedUndef

WIDTH = 100
_MOST_SIMPLIFY = 60


def simplify(e):
    """``sympy.simplify(e)``, the same expression, with the results of pure functions it calls kept while
    it runs: trigsimp's ``factor`` (the greedy search over Fu's rules factors one sum again after each rule
    that left it as it was, three to ten times over) and ``_futrig`` (that search, run on every node from
    the leaves up, and again on the nodes it has seen: 1058 searches over 206 nodes in 4.7, 4.12, 4.21 and
    4.33), ``simplify`` itself (it simplifies the arguments of every function again: sin(θ - φ) in each
    line) and ``count_ops``, its measure (asked 15500 times over 1700 expressions in a ``show --derive`` of
    every exercise).  What is returned is what sympy returns.  Where sympy no longer has one of them by
    that name, this is sympy's simplify unchanged."""
    plain = {}
    for (module, name) in _KEPT:
        f = getattr(importlib.import_module(module), name, None)
        if f is None or getattr(f, "remembers", False):
            return sp.simplify(e)
        plain[module, name] = f
    for (module, name), f in plain.items():
        setattr(importlib.import_module(module), name, _remembering(f, _KEPT[module, name]))
    try:  # the measure, count_ops remembered, is one function: simplify's results are kept under it
        return importlib.import_module("sympy.simplify.simplify").simplify(e, measure=_MEASURE)
    finally:
        for (module, name), f in plain.items():
            setattr(importlib.import_module(module), name, f)


# sympy's pure functions whose results ``simplify`` keeps, each with its results: a process's derivations
# share their subexpressions (the same node of 4.7's equations is searched over in each of its lines);
# count_ops, by whatever name it is called, keeps one table
_OPS: dict = {}
_KEPT: dict[tuple[str, str], dict] = {
    **{(m, n): {} for m, n in [("sympy.simplify.trigsimp", "factor"), ("sympy.simplify.trigsimp", "_futrig"),
                               ("sympy.simplify.simplify", "simplify")]},
    **{(m, "count_ops"): _OPS for m in ("sympy.core.function", "sympy.simplify.simplify",
                                        "sympy.simplify.trigsimp")}}


def _remembering(plain, kept: dict):
    def remembered(f, *gens, **args):
        try:
            key = (f, gens, tuple(sorted(args.items())))
            return kept[key]
        except KeyError:
            kept[key] = out = plain(f, *gens, **args)
            return out
        except TypeError:  # an argument that cannot be a key
            return plain(f, *gens, **args)

    remembered.remembers = True
    return remembered


def tidy(e, cache: dict | None = None):
    """``e`` simplified where that is quick: sin² + cos² taken out wherever a sum holds both with one
    coefficient (a turned frame leaves them in 4.31's Lagrangian), ``simplify`` on small expressions, common
    factors out of the rest (``trigsimp`` would take 80 s of CPU on 4.8's equations with friction)."""
    if cache is not None and e in cache:
        return cache[e]
    if cache is not None and isinstance(e, sp.Basic) and -e in cache:  # a reaction: the action's form, negated
        cache[e] = -cache[-e]
        return cache[e]
    out = e
    if isinstance(e, sp.Basic) and not isinstance(e, (sp.Symbol, sp.Number)):
        out = pythagoras(e)
        out = simplify(out) if sp.count_ops(out) <= _MOST_SIMPLIFY else sp.factor_terms(out)
        if sp.count_ops(out) > sp.count_ops(e):
            out = sp.factor_terms(e)
    if cache is not None:
        cache[e] = out
    return out


def pythagoras(e, rounds: int = 6):
    """``e`` with every pair c sin²x + c cos²x of a sum replaced by c, until none is left (sin³x + sin x cos²x
    is sin x after two rounds)."""
    for _ in range(rounds):
        if not (e.has(sp.sin) and e.has(sp.cos)):
            return e
        new = e.replace(lambda n: n.is_Add, _pythagoras)
        if new == e:
            return e
        e = new
    return e


def _pythagoras(total):
    """``total`` (a sum) with each pair c sin²x + c cos²x replaced by c (one pair a term)."""
    seen: dict = {}
    for k, term in enumerate(total.args):
        for factor in sp.Mul.make_args(term):
            if factor.is_Pow and factor.exp.is_Integer and factor.exp >= 2 and isinstance(factor.base, (sp.sin, sp.cos)):
                rest = term / factor.base**2
                seen.setdefault((rest, factor.base.args[0]), {})[type(factor.base)] = k
    drop, keep = set(), []
    for (rest, _), where in seen.items():
        if len(where) == 2 and not drop & set(where.values()):
            drop |= set(where.values())
            keep.append(rest)
    if not drop:
        return total
    return sp.Add(*[t for k, t in enumerate(total.args) if k not in drop], *keep)


class Shower:
    """Equations ``head = expr`` (or ``expr = 0``) as lines of at most ``WIDTH`` characters, for the
    terminal (sympy's pretty pictures) or LaTeX."""

    def __init__(self, latex: bool, taken: set[str], fold: bool = True, memo: dict | None = None):
        from sympy.physics.vector.printing import VectorPrettyPrinter

        self.latex = latex
        self.fold = fold or not latex  # False: one LaTeX string an equation (JSON), the same names
        self.pretty = VectorPrettyPrinter({"use_unicode": True, "wrap_line": False})
        self.prefix = next(p for p in "KQWYZ" + "ABCDEFGH" if not any(n.startswith(p) for n in taken))
        self.names: dict = {}  # a part named -> its name (shared by every equation shown)
        self.pending: list = []  # named, not yet defined on a line
        # what was drawn, kept (and shared by the text, LaTeX and JSON of one derivation, through ``memo``):
        # a line's width is tried for each term a line takes, and ``_fits`` draws what ``_packed`` draws again
        memo = {} if memo is None else memo
        self._widths: dict = memo.setdefault("widths", {})
        self._drawn: dict = memo.setdefault("drawn", {})

    # -- printing one piece
    def text(self, e) -> str:
        if self.latex:
            from sympy.physics.vector import vlatex

            return vlatex(e)
        return self.pretty.doprint(e)

    # -- naming the widest part of a term
    def _plain_width(self, e) -> int:
        if e not in self._widths:
            self._widths[e] = max(len(r) for r in self.pretty.doprint(e).split("\n"))
        return self._widths[e]

    def _name_widest(self, term):
        """``term`` with its widest proper part (a sum, a product, a function) named: the name it already
        has (a part met before keeps its name), or a new one; None when no part can be."""
        parts = [s for s in sp.preorder_traversal(term)
                 if s is not term and s.args and not s.is_Atom and not isinstance(s, (AppliedUndef, sp.Derivative))
                 and self._plain_width(s) >= 8]
        for widest in sorted(parts, key=self._plain_width, reverse=True):
            name = self.names.get(widest)
            if name is None:
                name = sp.Symbol(f"{self.prefix}_{len(self.names) + 1}")
            new = term.xreplace({widest: name})
            if new != term:
                if widest not in self.names:
                    self.names[widest] = name
                    self.pending.append((name, widest))
                return new
        return None

    def fit(self, expr, room: int, own=None):
        """``expr`` with parts named until each of its terms fits in ``room`` columns (a product of a sum
        multiplied out first where that is no longer: 4.31's L = m (...)/2 is a sum of short terms);
        ``own``: the part ``expr`` defines, not replaced by its own name."""
        expr = expr.xreplace({k: v for k, v in self.names.items() if k is not own and k != own})
        spread = pythagoras(sp.expand(expr))
        if spread.is_Add and sp.count_ops(spread) <= 2 * sp.count_ops(expr) + 4:
            expr = spread
        for _ in range(200):
            wide = [t for t in sp.Add.make_args(expr) if self._plain_width(t) > room]
            if not wide:
                return expr
            t = max(wide, key=self._plain_width)
            new = self._name_widest(t)
            if new is None:
                return expr
            expr = expr.xreplace({t: new})
        return expr

    # -- one equation
    def equation(self, head, expr, zero: bool = False) -> list[str]:
        """The lines of ``head = expr`` (``expr = 0`` when ``zero``; ``expr`` alone when ``head`` is None;
        a ``head`` given as text is printed as it is), then of each part it names to fit (a part named
        before, in this equation or an earlier one, keeps its name)."""
        if not isinstance(expr, sp.Basic) or isinstance(expr, (sp.Equality, sp.MatrixBase)):
            return self.wrap(self.text(expr))
        if self._fits(head, expr, zero):
            return self._packed(head, expr, zero)
        lead = 0 if head is None or zero else (len(head) if isinstance(head, str) else self._plain_width(head)) + 3
        lines = self._packed(head, self.fit(expr, WIDTH - max(8, lead)), zero)
        first = True
        while self.pending:  # a named part may name parts of its own
            name, part = self.pending.pop(0)
            if first:
                lines.append(r"\text{where}" if self.latex else "where")
                first = False
            lines += self._packed(name, self.fit(part, WIDTH - max(8, self._plain_width(name) + 3), own=part), False)
        return lines

    def _fits(self, head, expr, zero) -> bool:
        """Does ``head = expr`` fit in lines of ``WIDTH`` as the terminal shows it (LaTeX takes the same
        names as the text, so that both read alike)?"""
        latex, self.latex = self.latex, False
        try:
            return all(len(r) <= WIDTH for line in self._packed(head, expr, zero) for r in line.split("\n"))
        finally:
            self.latex = latex

    def vector(self, label: str, v, cache: dict | None = None) -> list[str]:
        """``label:`` and a vector, a line (or more) per component along its frame's axes."""
        from mech.problems.derive_text import tidy

        if not hasattr(v, "args") or not isinstance(v.args, list):
            return self.wrap(f"{label}: " + self.text(v))
        terms = []
        for matrix, frame in v.args:
            for i, c in enumerate(matrix):
                if c != 0:
                    terms.append(tidy(c, cache) * sp.Symbol(f"{str(frame.name).lower()}_{'xyz'[i]}"))
        if not terms:
            return [f"{label}: 0"]
        return [f"{label}:"] + [line for t in terms for line in self.equation(None, t)]

    def _packed(self, head, expr, zero: bool) -> list[str]:
        terms = list(expr.as_ordered_terms()) if expr.is_Add else [expr]
        chunks: list[list] = [[]]
        for t in terms:
            trial = chunks[-1] + [t]
            if chunks[-1] and self.fold and self._line_width(head, trial, zero, len(chunks) == 1) > WIDTH:
                chunks.append([t])
            else:
                chunks[-1] = trial
        out = []
        for k, chunk in enumerate(chunks):
            out += self._render(head, chunk, zero and k == len(chunks) - 1, k == 0)
        return out

    def _line_width(self, head, chunk, zero, first) -> int:
        return max(len(r) for line in self._render(head, chunk, zero, first) for r in line.split("\n"))

    def _render(self, head, chunk, zero, first) -> list[str]:
        key = (self.latex, self.fold, type(head), head, tuple(chunk), zero, first)
        if key not in self._drawn:
            self._drawn[key] = self._draw(head, chunk, zero, first)
        return list(self._drawn[key])

    def _draw(self, head, chunk, zero, first) -> list[str]:
        lead = chunk[0]
        sign = ""
        if not first:  # a continuation line opens with its sign
            sign = "- " if lead.could_extract_minus_sign() else "+ "
            if sign == "- ":
                chunk = [-lead] + chunk[1:]
        body = sp.Add(*chunk, evaluate=False) if len(chunk) > 1 else chunk[0]
        named = first and head is not None and not zero
        if self.latex:
            from sympy.physics.vector import vlatex

            left = ""
            if named:
                left = (r"\mathrm{" + head.replace("_", r"\_") + "}" if isinstance(head, str) else vlatex(head)) + " = "
            return self.wrap(("    " + sign if not first else "") + left + vlatex(body) + (" = 0" if zero else ""))
        from sympy.printing.pretty.stringpict import prettyForm

        pic = self.pretty._print(body)
        if named:
            left = prettyForm(head) if isinstance(head, str) else self.pretty._print(head)
            pic = prettyForm(*left.right(" = ", pic))
        if not first:
            pic = prettyForm(*pic.left("    " + sign))
        if zero:
            pic = prettyForm(*pic.right(" = 0"))
        return [pic.render(wrap_line=False)]

    # -- LaTeX and plain text cut at operators or spaces
    def wrap(self, text: str) -> list[str]:
        if "\n" in text and not self.latex:  # a picture (a matrix) comes on lines of its own, under its words
            words, _, picture = text.partition("\n")
            return wrap_plain(words) + [picture]
        if self.latex:
            return wrap_latex(text) if self.fold else [text]
        return wrap_plain(text)


def wrap_plain(text: str) -> list[str]:
    return textwrap.wrap(text, WIDTH, subsequent_indent="    ", break_long_words=True, break_on_hyphens=False) or [""]


def wrap_latex(text: str) -> list[str]:
    """LaTeX cut into lines of at most ``WIDTH``: before a top-level ``+``, ``-`` or ``=``, else at a space,
    else after a closing brace (a line break in LaTeX source is a space)."""
    lines = []
    while len(text) > WIDTH:
        cut = _latex_cut(text)
        lines.append(text[:cut].rstrip())
        text = "    " + text[cut:].lstrip()
    lines.append(text)
    return lines


def _latex_cut(text: str) -> int:
    depth, top, space, brace = 0, 0, 0, 0
    i = 0
    while i < len(text) and i <= WIDTH:
        ch = text[i]
        if text.startswith(r"\left", i):
            depth += 1
        elif text.startswith(r"\right", i):
            depth -= 1
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
            brace = i + 1
        elif ch == " " and i > 4:
            space = i
            if depth == 0 and text[i + 1:i + 2] in ("+", "-", "="):
                top = i
        i += 1
    return top or space or brace or WIDTH


_MEASURE = _remembering(sp.count_ops, _OPS)
