"""Baselines for CI across upgrades: every checked value with its error bar, and what moved since.

A baseline records, for every point ``mech check`` ran (an exercise's defaults
and hard cases), every output's analytic value, numeric value and their error
bars (``numeric_err``; ``analytic_err`` where the exercise declares one), with
the versions of mech, numpy, scipy and Python.  Compared with a later run, a
value has moved when the two differ by more than their combined error bars
(the old one's plus the new one's) plus ``ROUND_OFF`` relative: two honest
runs of a correct solver never move.  Verification logic only; no physics.
"""

from __future__ import annotations

import datetime as _dt
import json
import math
import platform
from dataclasses import dataclass, field

from mech.core.errors import BadInput
from mech.problems.spec import Undefined
from mech.verification.judge import ROUND_OFF, allowance, analytic_err, within

__all__ = ["FORMAT", "record_case", "make", "validate", "compare", "Comparison", "Move", "open_baseline", "check_records", "baselines"]

FORMAT = "mech-baseline"
VERSION = 1


def _finite(v):
    return float(v) if isinstance(v, float) and math.isfinite(v) else None


def record_case(ex_id: str, label: str, params, ok: bool, quantities) -> dict:
    """One checked point: its parameters (SI) and, per output, the values with their error bars."""
    outputs = {}
    for q in quantities or []:
        o = {"unit": q.unit, "analytic": _finite(q.analytic), "numeric": _finite(q.numeric)}
        err = getattr(q, "numeric_err", None)
        o["numeric_err"] = _finite(err) if o["numeric"] is not None else None
        if o["analytic"] is not None and getattr(q, "analytic_err", None) is not None:
            o["analytic_err"] = _finite(analytic_err(q))
        undefined = [f"{k}: {v.why}" for k, v in (("analytic", q.analytic), ("numeric", q.numeric))
                     if isinstance(v, Undefined)]
        if undefined:
            o["note"] = "; ".join(undefined)
        outputs[q.name] = o
    return {"id": ex_id, "case": label, "params": {k: float(v) for k, v in dict(params or {}).items()},
            "ok": bool(ok), "outputs": outputs}


DISTRIBUTION = "mech-likharev"  # mech's distribution name on the package index (the import name is mech)


def versions() -> dict:
    """The versions the values were computed with (read from the installed metadata: no scipy import)."""
    from importlib import metadata

    out = {"python": platform.python_version()}
    for key, dist in (("mech", DISTRIBUTION), ("numpy", "numpy"), ("scipy", "scipy")):
        try:
            out[key] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[key] = None
    return out


def make(records: list[dict], hard: bool) -> dict:
    return {"format": FORMAT, "version": VERSION,
            "created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
            "versions": versions(), "hard": bool(hard), "cases": records}


def _number(v, *, nullable: bool = True, nonnegative: bool = False) -> str | None:
    """What is wrong with a value that must be a finite JSON number (or null), or None."""
    if v is None:
        return None if nullable else "missing"
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        return f"not a number ({type(v).__name__})"
    try:
        x = float(v)
    except OverflowError:
        return "not a finite number (too large)"
    if not math.isfinite(x):
        return "not a finite number"
    if nonnegative and x < 0:
        return f"negative ({x:g}); an error bar is at least 0"
    return None


def validate(data) -> str | None:
    """What is wrong with a loaded baseline (the field named), or None.  Every field a comparison reads is
    checked here, before the check runs: its type, its presence, error bars non-negative."""
    if not isinstance(data, dict) or data.get("format") != FORMAT:
        return f"format: not a mech baseline (no \"format\": \"{FORMAT}\")"
    version = data.get("version")
    if isinstance(version, bool) or version != VERSION:
        return f"version: {str(version)[:40]!r}, this mech reads version {VERSION}"
    vers = data.get("versions", {})
    if not isinstance(vers, dict) or not all(isinstance(k, str) and (v is None or isinstance(v, str))
                                             for k, v in vers.items()):
        return "versions: not an object of version strings (such as {\"numpy\": \"2.1.0\"})"
    if "hard" in data and not isinstance(data["hard"], bool):
        return "hard: not true or false"
    if "created" in data and not isinstance(data["created"], str):
        return "created: not a string"
    cases = data.get("cases")
    if not isinstance(cases, list):
        return "cases: missing or not a list"
    seen = set()
    for k, c in enumerate(cases):
        if not isinstance(c, dict) or not isinstance(c.get("id"), str) or not isinstance(c.get("case"), str):
            return f"cases[{k}]: needs \"id\" and \"case\" strings"
        where = f"cases[{k}] ({c['id'][:20]} {c['case'][:40]})"
        if (c["id"], c["case"]) in seen:
            return f"{where}: given twice"
        seen.add((c["id"], c["case"]))
        if not isinstance(c.get("params"), dict) or not isinstance(c.get("outputs"), dict):
            return f"{where}: needs \"params\" and \"outputs\" objects"
        if "ok" in c and not isinstance(c["ok"], bool):
            return f"{where}: ok: not true or false"
        for name, v in c["params"].items():
            problem = _number(v, nullable=False)
            if problem:
                return f"{where}: params.{str(name)[:40]}: {problem}"
        if not c["outputs"] and c.get("ok", True):
            return f"{where}: outputs: empty for a case that passed"
        for name, o in c["outputs"].items():
            field_name = f"{where}: outputs.{str(name)[:40]}"
            if not isinstance(o, dict):
                return f"{field_name}: not an object"
            if "unit" in o and not isinstance(o["unit"], str):
                return f"{field_name}.unit: not a string"
            for key in ("analytic", "numeric", "numeric_err", "analytic_err"):
                problem = _number(o.get(key), nonnegative=key.endswith("_err"))
                if problem:
                    return f"{field_name}.{key}: {problem}"
            for key in ("analytic", "numeric"):
                if key not in o:
                    return f"{field_name}.{key}: missing (null where there is no value)"
    return None


@dataclass
class Move:
    id: str
    case: str
    output: str
    which: str  # "analytic", "numeric", "params", "outputs"
    old: float | None = None
    new: float | None = None
    allowed: float | None = None
    why: str = ""

    def text(self) -> str:
        where = f"{self.id} {self.case}" + (f" {self.output}" if self.output else "")
        if self.why:
            return f"{where}: {self.why}"
        return (f"{where} {self.which}: {self.old:.12g} -> {self.new:.12g} (moved {abs(self.new - self.old):.2g}, "
                f"error bars allow {self.allowed:.2g})")

    def as_json(self) -> dict:
        return {"id": self.id, "case": self.case, "output": self.output, "which": self.which, "old": self.old,
                "new": self.new, "allowed": self.allowed, "why": self.why or None}


@dataclass
class Comparison:
    path: str
    moved: list[Move] = field(default_factory=list)
    compared: int = 0  # values compared
    not_in_baseline: list[str] = field(default_factory=list)  # points checked now that the baseline lacks
    points: list[tuple[str, str]] = field(default_factory=list)  # (id, case) of every point compared
    versions_then: dict = field(default_factory=dict)
    versions_now: dict = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        return not self.moved

    def as_json(self) -> dict:
        return {"file": self.path, "ok": self.ok, "compared": self.compared,
                "moved": [m.as_json() for m in self.moved], "not_in_baseline": self.not_in_baseline,
                "versions_then": self.versions_then, "versions_now": self.versions_now}


def _bar(o: dict, which: str) -> float:
    return float(o.get(f"{which}_err") or 0.0)


def compare(baseline: dict, records: list[dict], path: str = "") -> Comparison:
    """The values of ``records`` (this run) that moved beyond their combined error bars since ``baseline``."""
    cmp = Comparison(path, versions_then=dict(baseline.get("versions") or {}), versions_now=versions())
    then = {(c["id"], c["case"]): c for c in baseline["cases"]}
    for rec in records:
        old_case = then.get((rec["id"], rec["case"]))
        if old_case is None:
            cmp.not_in_baseline.append(f"{rec['id']} {rec['case']}")
            continue
        cmp.points.append((rec["id"], rec["case"]))
        if old_case["params"] != rec["params"]:
            changed = sorted(k for k in set(old_case["params"]) | set(rec["params"])
                             if old_case["params"].get(k) != rec["params"].get(k))
            cmp.moved.append(Move(rec["id"], rec["case"], "", "params",
                                  why=f"parameters differ from the baseline's ({', '.join(changed)}): "
                                      "the values cannot be compared"))
            continue
        for name, old in old_case["outputs"].items():
            new = rec["outputs"].get(name)
            if new is None:
                if rec["outputs"]:  # no outputs at all is a failed case, already reported by the check
                    cmp.moved.append(Move(rec["id"], rec["case"], name, "outputs", why="no longer an output"))
                continue
            for which in ("analytic", "numeric"):
                a, b = old.get(which), new.get(which)
                if a is None and b is None:
                    continue
                cmp.compared += 1
                if a is None or b is None:
                    state = "now has a finite value" if a is None else "no longer has a finite value"
                    cmp.moved.append(Move(rec["id"], rec["case"], name, which, a, b, why=f"{which} {state}"))
                    continue
                held = dict(scale=max(abs(a), abs(b)), bars=(_bar(old, which), _bar(new, which)), round_off=ROUND_OFF)
                if not within(abs(b - a), **held):
                    cmp.moved.append(Move(rec["id"], rec["case"], name, which, a, b, allowance(**held)))
    return cmp


# -- mech check --save-baseline / --baseline: the files ------------------------------------------------

def open_baseline(path: str) -> dict:
    """A baseline file, read and checked before the run (BadInput: one line naming the file and field)."""
    from mech.core.safeio import load_json, shown, shown_path
    data = load_json(path, "baseline")  # a regular file under 10 MB, nesting bounded, finite numbers
    problem = validate(data)
    if problem:
        raise BadInput(f"{shown_path(path)}: {shown(problem, 300)}")
    return data


def check_records(report) -> list[dict]:
    return [record_case(c.exercise.id, c.label, getattr(c.result, "params", None) or c.given, c.ok,
                                 getattr(c.result, "quantities", None)) for c in report.cases]


def baselines(report, hard: bool, old: dict | None, old_path: str | None, save_path: str | None):
    """Compare this check with a loaded baseline and/or save it as one; the Comparison or None."""
    records = check_records(report)
    cmp = compare(old, records, old_path or "") if old is not None else None
    if save_path:
        from mech.core.safeio import atomic_write

        text = json.dumps(make(records, hard), indent=1, allow_nan=False) + "\n"
        with atomic_write(save_path, "--save-baseline") as fh:  # a failed write leaves the old file whole
            fh.write(text)
    return cmp
