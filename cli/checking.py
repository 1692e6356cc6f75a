"""``mech check``'s JUnit report; the cases are run by ``mech.verification.checking``."""

from __future__ import annotations

from xml.etree import ElementTree as ET

from mech.verification.checking import Report

__all__ = ["write_junit"]


def write_junit(report: Report, path: str) -> None:
    suite = ET.Element("testsuite", name="mech check", tests=str(len(report.cases)), failures=str(report.failed),
                       errors="0", time=f"{report.seconds:.3f}")
    for case in report.cases:
        # "mech.4.15" reads as package mech.4, class 15 in CI viewers: the id's dot becomes an underscore
        tc = ET.SubElement(suite, "testcase", classname=f"mech.ex{case.exercise.id.replace('.', '_')}",
                           name=f"{case.exercise.id} {case.description}", time=f"{case.seconds:.3f}")
        if not case.ok:
            fail = ET.SubElement(tc, "failure", message=case.detail or "cross-check failed")
            fail.text = case.detail
    root = ET.Element("testsuites", name="mech", tests=str(len(report.cases)), failures=str(report.failed))
    root.append(suite)
    ET.indent(root)
    from mech.core.safeio import atomic_write

    with atomic_write(path, "--junit", mode="wb") as fh:  # a failed write leaves the old report whole
        ET.ElementTree(root).write(fh, encoding="utf-8", xml_declaration=True)
