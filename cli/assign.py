"""``mech assign``: personal variants for a class, with their handout, answers template and key.

The drawing and verifying is ``mech.students.assign`` (through ``mech.api.assign``).
"""

from __future__ import annotations

import click

__all__ = ["assign_cmd"]


@click.command("assign")
@click.argument("ids", nargs=-1, required=True, metavar="ID [ID ...]")
@click.option("--students", "students", metavar="FILE", help="The roster: one student identifier a line.")
@click.option("--n", "n", metavar="N", help="N students named s1 ... sN (instead of --students).")
@click.option("--seed", "seed", metavar="S", required=True, help="The draw's seed: the same seed, the same files.")
@click.option("--out", "out", metavar="DIR", required=True,
              help="The folder to write the handouts, the answers templates and the key into.")
@click.option("--over", "over", metavar="NAME=LO:HI", multiple=True,
              help="Draw a parameter inside LO:HI (within its bounds), or fix it with NAME=VALUE (g=9.81); "
                   "ID:NAME=... for one exercise only. E.g. theta0=10deg:80deg.")
@click.option("--digits", "digits", metavar="D", default="3", show_default=True,
              help="Significant digits of each value, in the unit the handout prints.")
@click.option("--force", is_flag=True, help="Replace the assignment DIR already holds.")
@click.option("-j", "--jobs", type=click.IntRange(1, 256), metavar="N", help="Processes to solve with [one per core].")
def assign_cmd(ids, students, n, seed, out, over, digits, force, jobs):
    """Personal variants for a class: each student's parameters drawn, rounded and verified, with the key.

    Each student gets values drawn inside each parameter's typical range (within a factor 3 of the
    textbook value; g and the Earth's constants fixed unless --over opens them) and the joint
    constraints, rounded to --digits significant digits. A variant is issued only where both methods
    agree, every output has a value, every leading-order answer lies within 1 % of the exact one and
    the statement's regime holds; otherwise the student takes the next draw.

    Writes DIR/handout.md and DIR/handouts/STUDENT.md, DIR/answers.toml and DIR/answers.csv (the
    templates, every answer empty), DIR/key.json, DIR/key.csv and DIR/key.md. The same roster, seed
    and mech version give the same files, byte for byte. A DIR already holding an assignment is
    refused unless --force.
    """
    from mech import api
    from mech.core.safeio import shown_path

    key = api.assign(list(ids), seed=seed, out=out, students=students, n=n, over=list(over), digits=digits,
                     jobs=jobs, force=force)
    n_students = len({v["student"] for v in key["variants"]})
    click.echo(f"{len(key['variants'])} variants ({n_students} students x {len(ids)} exercise{'' if len(ids) == 1 else 's'}), each verified, "
               f"written to {shown_path(out)}: handout.md, handouts/, answers.toml, answers.csv, key.json, key.csv, key.md")
