"""The printing of ``mech check``'s baseline comparison: its lines in the report and its JUnit suite."""

from __future__ import annotations

__all__ = ["junit_baseline", "print_baseline"]


def junit_baseline(junit_file: str, cmp) -> None:
    """Add to ``mech check``'s JUnit report a suite with one test case per point compared with the
    baseline, failed when any of its values moved: CI shows what moved, not only the exit status."""
    from xml.etree import ElementTree as ET

    tree = ET.parse(junit_file)
    root = tree.getroot()
    moved: dict[tuple[str, str], list[str]] = {}
    for m in cmp.moved:
        moved.setdefault((m.id, m.case), []).append(m.text())
    suite = ET.SubElement(root, "testsuite", name=f"mech baseline {cmp.path}", tests=str(len(cmp.points)),
                          failures=str(len(moved)), errors="0")
    for ex_id, case in cmp.points:
        tc = ET.SubElement(suite, "testcase", classname=f"mech.baseline.ex{ex_id.replace('.', '_')}", name=case)
        if (ex_id, case) in moved:
            fail = ET.SubElement(tc, "failure", message="moved beyond its error bars since the baseline")
            fail.text = "\n".join(moved[(ex_id, case)])
    root.set("tests", str(int(root.get("tests", "0")) + len(cmp.points)))
    root.set("failures", str(int(root.get("failures", "0")) + len(moved)))
    ET.indent(root)
    from mech.core.safeio import atomic_write

    with atomic_write(junit_file, "--junit", mode="wb") as fh:
        tree.write(fh, encoding="utf-8", xml_declaration=True)


def print_baseline(cmp, saved: str | None) -> None:
    from rich.text import Text

    from mech import render

    c = render.console()
    if cmp is not None:
        then = cmp.versions_then
        changed = [f"{k} {then.get(k)} -> {v}" for k, v in cmp.versions_now.items() if then.get(k) != v]
        since = f" (since: {', '.join(changed)})" if changed else ""
        if cmp.ok:
            c.print(Text(f"baseline {cmp.path}: {cmp.compared} values, none moved beyond its error bars{since}",
                         style="green"))
        else:
            c.print(Text(f"baseline {cmp.path}: {len(cmp.moved)} of {cmp.compared} values moved beyond their "
                         f"error bars{since}:", style="bold red"))
            for m in cmp.moved:
                c.print(Text(f"  {m.text()}", style="red"))
        if cmp.not_in_baseline:
            c.print(Text(f"not in the baseline: {', '.join(cmp.not_in_baseline)}", style="yellow"))
    if saved:
        c.print(Text(f"baseline saved to {saved}", style="dim"))
