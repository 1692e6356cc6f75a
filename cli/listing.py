"""``mech list`` as a plain text table: the one command that should not pay for rich.

rich's import and its table layout (measuring every cell) took 0.08-0.1 s of a
0.25 s ``mech list``, whose budget is 0.3 s; this lays the same four columns
out with textwrap.  The last column says what differs between exercises: whether
the analytic values are exact or a leading-order theory (every exercise has both
methods; the source shows as the mark on the id).  Width: the terminal's, or 160 columns when piped (as the
rich renderings use).
"""

from __future__ import annotations

import shutil
import sys
import textwrap



def table_lines(exercises, width: int) -> list[str]:
    mark = _mark()
    rows = [(e.id + ("" if e.from_book else mark), e.title, e.topic,
             e.theory if "analytic" in e.methods else "numeric only") for e in exercises]
    id_w = max([2] + [len(r[0]) for r in rows])
    meth_w = max([len("analytic")] + [len(r[3]) for r in rows])
    free = max(30, width - id_w - meth_w - 8)  # 2 spaces between 4 columns, 1 at each edge
    title_w = max(12, free // 2)
    topic_w = max(12, free - title_w)
    out = [f" {'id':<{id_w}}  {'title':<{title_w}}  {'topic':<{topic_w}}  {'analytic':<{meth_w}}".rstrip()]
    out.append(_rule() * min(width, id_w + title_w + topic_w + meth_w + 8))
    for ex_id, title, topic, methods in rows:
        t = textwrap.wrap(title, title_w) or [""]
        p = textwrap.wrap(topic, topic_w) or [""]
        for k in range(max(len(t), len(p))):
            cells = (ex_id if k == 0 else "", t[k] if k < len(t) else "", p[k] if k < len(p) else "",
                     methods if k == 0 else "")
            out.append(f" {cells[0]:<{id_w}}  {cells[1]:<{title_w}}  {cells[2]:<{topic_w}}  {cells[3]:<{meth_w}}".rstrip())
    if any(not e.from_book for e in exercises):
        out += textwrap.wrap(f"{mark} set for mech on the chapter's topics; the others are the book's own "
                             "exercises", max(width, 30))
    out.append(f"{len(rows)} exercises")
    return out


def _mark() -> str:
    """The dagger that flags an exercise not from the book, or '+' where the output cannot encode it."""
    try:
        "†".encode(sys.stdout.encoding or "ascii")
        return "†"
    except (UnicodeEncodeError, LookupError):
        return "+"


def _rule() -> str:
    """The box-drawing rule where the output can encode it, a hyphen where it cannot."""
    try:
        "─".encode(sys.stdout.encoding or "ascii")
        return "─"
    except (UnicodeEncodeError, LookupError):
        return "-"


def print_list(exercises) -> None:
    from mech.core.safeio import columns

    width = columns()
    if width is None:
        width = shutil.get_terminal_size((160, 24)).columns if sys.stdout.isatty() else 160
    sys.stdout.write("\n".join(table_lines(exercises, width)) + "\n")


def print_derivation(ex, latex: bool = False, as_json: bool = False) -> None:
    """``mech show ID --derive``: the declared physics and the derived equations (``ex.derive()``), as
    terminal text, LaTeX, or JSON carrying the LaTeX strings; an exercise without a declaration says why
    (exit 0).  Without sympy, ``ex.derive()`` raises BadUsage (exit 2, how to install it)."""
    import json

    try:
        der = ex.derive()
    except LookupError as exc:
        why = str(exc.args[0]) if exc.args else "nothing is declared"
        if as_json:
            sys.stdout.write(json.dumps({"id": ex.id, "derived": False, "why": why}, indent=2) + "\n")
        else:
            sys.stdout.write(f"{ex.id}: no derivation: {why}\n")
        return
    if as_json:
        sys.stdout.write(json.dumps({"id": ex.id, "derived": True, **der.as_json()}, indent=2) + "\n")
        return
    rule = _rule()
    head = f"{ex.id} {ex.title}: physics declared, equations derived by sympy.physics.mechanics"
    out = [*textwrap.wrap(head, 100, subsequent_indent="    "), "", f"{rule * 2} declared",
           *(row for line in der.declared() for row in textwrap.wrap(line, 100, subsequent_indent="    "))]
    for heading, lines in der.sections(latex=latex):
        out.append("")
        out.append(f"{rule * 2} {heading}")
        out.extend(row.rstrip() for line in lines for row in line.split("\n"))
    sys.stdout.write("\n".join(out) + "\n")
