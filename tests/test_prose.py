"""Prose names only the ranges of exercises the registry defines.

A range of ids (the first and the last joined by a dash) in a README, a help text or a docstring goes
stale silently when an exercise is added: the ids set for mech, written as a range, miss the new one.  So a range may name only a block the registry itself defines: a chapter's registered
ids, or a run of them that are all the book's own or all set for mech (catalogue ``from_book``); any
other set of exercises is listed id by id.  The blocks are worked out here from the catalogue files.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CATALOGUE = ROOT / "problems" / "catalogue"
RANGE = re.compile(r"(?<![\d.])(\d+)\.(\d+) ?[-–] ?(\d+)\.(\d+)(?![\d.])")


def _blocks() -> set[tuple[int, int, int]]:
    """(chapter, first, last) of every chapter and of every run of equal ``from_book`` within one."""
    books: dict[int, list[tuple[int, bool]]] = {}
    for path in CATALOGUE.glob("*.toml"):
        chapter, number = map(int, path.stem.split("."))
        books.setdefault(chapter, []).append((number, tomllib.loads(path.read_text("utf-8"))["from_book"]))
    blocks = set()
    for chapter, items in books.items():
        items.sort()
        blocks.add((chapter, items[0][0], items[-1][0]))
        start = 0
        for k in range(1, len(items) + 1):
            if k == len(items) or items[k][1] != items[start][1] or items[k][0] != items[k - 1][0] + 1:
                blocks.add((chapter, items[start][0], items[k - 1][0]))
                start = k
    return blocks


def _prose_files() -> list[Path]:
    files = [ROOT / "README.md", ROOT / "DEVELOPING.md", *sorted((ROOT / "docs").glob("*.md"))]
    for folder in ("api", "cli", "core", "figures", "problems", "scripts", "solvers", "studies", "students", "tests", "verification"):
        files += sorted((ROOT / folder).rglob("*.py"))
    return [f for f in files if f.is_file()]


def test_the_blocks_are_worked_out_from_the_catalogue():
    blocks = _blocks()
    assert (4, 1, 36) in blocks and (5, 1, 3) in blocks  # the contract: 4.1-4.36 and 5.1-5.3 are the book's
    assert not any(c == 5 and a == 1 and b < 3 for c, a, b in blocks)


def test_prose_names_no_range_the_registry_does_not_define():
    blocks = _blocks()
    chapters = {c for c, _, _ in blocks}
    stale = []
    for path in _prose_files():
        for k, line in enumerate(path.read_text("utf-8").splitlines(), 1):
            for m in RANGE.finditer(line):
                c1, a, c2, b = map(int, m.groups())
                if c1 == c2 and c1 in chapters and (c1, a, b) not in blocks:
                    stale.append(f"{path.relative_to(ROOT)}:{k}: {m.group(0)}")
    assert not stale, "ranges the registry does not define (list the ids, or name a chapter): " + "; ".join(stale)
