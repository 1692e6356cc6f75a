"""Issue 40 items 5 and 7: ``mech.assign`` refuses every bad argument with BadInput before any work, and
the escaping helpers (``safeio.csv_cell``, ``md_text``, ``slugs``) hold for any text."""

import os
import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import mech
from mech.core.safeio import csv_cell, csv_uncell, md_text, slugs


class _BadPath:
    def __fspath__(self):
        raise RuntimeError("no")


class _BadStr:
    def __str__(self):
        raise RuntimeError("no")

    __repr__ = __str__


# for each argument: values that must be refused (the other arguments valid)
HOSTILE = {
    "ids": [4.15, 415, None, object(), [4.15], ["4.15", 3], ["4.99"], [], range(10**9), ["4.15"] * 10**6, b"4.15",
            {"4.15": 1}, "x" * 10**6, _BadStr()],
    "seed": [-1, 2**64, "x", 1.5, object(), True, [1], "9" * 10**6, _BadStr()],
    "out": [object(), 12, None, b"/tmp/x", "", "a\x00b", _BadPath(), ["a"], "x" * 10**6, _BadStr()],
    "students": [12, object(), [1, 2], ["ann", None], ["ann", "ann"], ["x" * 500], [], ["ann"] * 10**6,
                 range(10**9), _BadStr(), "a\x00b", ["a\x1bb"]],
    "n": [0, -1, 10**9, "x", 1.5, object(), True, [3], _BadStr()],
    "over": [range(10**9), object(), 12, [1, 2], {"theta0": 1}, {1: "1:2"}, ["theta0"], ["zzz=1:2"],
             ["theta0=80deg:10deg"], ["theta0=1:2:3"], {"theta0": "10deg:100deg"}, ["g=-1"], ["g=nan"],
             ["theta0=1e999"], ["g=1:2"] * 10**6, {str(i): "1:2" for i in range(2000)}, _BadStr()],
    "digits": [0, 1, 13, "x", 1.5, object(), None, True, _BadStr()],
    "jobs": [0, -1, "x", 1.5, object(), True, _BadStr()],
    "force": ["yes", 1, None, object(), _BadStr()],
}


def _call(tmp_path, name, value):
    args = {"ids": ["4.15"], "seed": 1, "out": str(tmp_path / "o"), "n": 2}
    if name == "students":
        args.pop("n")
    args[name] = value
    ids = args.pop("ids")
    return mech.assign(ids, **args)


@pytest.mark.parametrize("name, value", [(k, v) for k, vs in HOSTILE.items() for v in vs],
                         ids=lambda x: x if isinstance(x, str) and len(x) < 20 else type(x).__name__)
def test_each_hostile_argument_is_bad_input_before_any_work(tmp_path, name, value):
    with pytest.raises(mech.BadInput) as exc:
        _call(tmp_path, name, value)
    message = str(exc.value)
    assert "\n" not in message and len(message) < 400 and "Traceback" not in message
    assert not (tmp_path / "o" / "key.json").exists()


_ANY = st.one_of(st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True), st.text(max_size=30),
                 st.binary(max_size=10), st.lists(st.integers(), max_size=3), st.dictionaries(st.text(max_size=5),
                                                                                              st.integers(), max_size=2))


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(name=st.sampled_from(["ids", "seed", "out", "students", "n", "over", "digits", "jobs", "force"]), value=_ANY)
def test_any_argument_gives_bad_input_or_a_valid_class(tmp_path, name, value):
    """Whatever one argument is, assign raises BadInput (never TypeError, ValueError, MemoryError ...) unless
    it is valid; a valid class of 4.15 is cheap."""
    small = isinstance(value, int) and not isinstance(value, bool) and value >= 1
    if name == "n" and small and value <= 2000 or name == "jobs" and small and value <= 256:
        value = 1  # valid: a class of one, one process (the check of the value is the same)
    if name == "out" and isinstance(value, str) and value.strip():
        value = str(tmp_path / "h" / re.sub(r"[^A-Za-z0-9]", "_", value))  # a path of that name, inside tmp
    try:
        _call(tmp_path, name, value)
    except mech.BadInput as exc:
        assert "\n" not in str(exc)
    else:
        import shutil

        shutil.rmtree(tmp_path / "o", ignore_errors=True)
        shutil.rmtree(tmp_path / "h", ignore_errors=True)


_FORMULA = re.compile(r"^[ \u00a0]*[=+\-@\t\r]")


@settings(deadline=None)
@given(st.text(max_size=60))
def test_csv_cell_leaves_no_part_a_formula_and_comes_back(text):
    cell = csv_cell(text)
    assert csv_uncell(cell) == text
    if re.fullmatch(r" *[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)? *([A-Za-z/][A-Za-z0-9^*/. ]*)?", text):
        return  # a number with its unit: no call, no separator
    for part in re.split(r"[,;\t|\r\n]", cell):
        assert not _FORMULA.match(part) or part.lstrip(" \u00a0").startswith("'")


def test_csv_cell_by_hand():
    assert csv_cell('a;=HYPERLINK("x")') == "a;'=HYPERLINK(\"x\")"
    assert csv_cell("=1+1") == "'=1+1" and csv_cell("-1.5") == "-1.5" and csv_cell("-0.03 m/s") == "-0.03 m/s"
    assert csv_cell("x|@SUM(A1)") == "x|'@SUM(A1)" and csv_cell("bob") == "bob"


@settings(max_examples=300, deadline=None)
@given(st.text(max_size=40))
def test_md_text_renders_as_the_text_itself(text):
    """Rendered by a CommonMark renderer inside a paragraph, an escaped name is one paragraph of literal
    text: no tag, no link, no image, no code, no emphasis."""
    from markdown_it import MarkdownIt

    html = MarkdownIt("commonmark").render("x " + md_text(text))
    tags = set(re.findall(r"<(/?\w+)", html))
    assert tags <= {"p", "/p"}, (text, html)


@settings(deadline=None)
@given(st.lists(st.text(max_size=30), max_size=12))
def test_slugs_are_safe_and_unique(names):
    got = slugs(names)
    assert len(got) == len(names)
    assert len({s.lower() for s in got}) == len(got)
    for s in got:
        assert re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_-]*", s) and len(s) <= 64
        assert os.path.basename(s) == s and s.lower().split("-")[0] not in {"con", "nul", "prn", "aux"}
