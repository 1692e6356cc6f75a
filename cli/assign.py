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
@click.option("--out", "out", metavar="DIR", required=True, help="The folder to write handout.md, answers.toml, key.json.")
@click.option("--over", "over", metavar="NAME=LO:HI", multiple=True,
              help="Narrow a parameter's range (ID:NAME=LO:HI for one exercise only), e.g. theta0=10deg:80deg.")
@click.option("--digits", "digits", metavar="D", default="3", show_default=True,
              help="Significant digits of each value, in the unit the handout prints.")
@click.option("-j", "--jobs", type=click.IntRange(1, 256), metavar="N", help="Processes to solve with [one per core].")
def assign_cmd(ids, students, n, seed, out, over, digits, jobs):
    """Personal variants for a class: each student's parameters drawn, rounded and verified, with the key.

    Each student gets values drawn inside the declared ranges and joint constraints, rounded to
    --digits significant digits; each rounded variant is solved by both methods and redrawn unless
    they agree. Writes DIR/handout.md, DIR/answers.toml (the grading file, every answer "") and
    DIR/key.json. The same roster, seed and mech version give the same files, byte for byte.
    """
    from mech import api
    from mech.core.safeio import shown_path

    key = api.assign(list(ids), seed=seed, out=out, students=students, n=n, over=list(over), digits=digits,
                     jobs=jobs)
    n_students = len({v["student"] for v in key["variants"]})
    click.echo(f"{len(key['variants'])} variants ({n_students} students x {len(ids)} exercise{'' if len(ids) == 1 else 's'}), each verified, "
               f"written to {shown_path(out)}: handout.md, answers.toml, key.json")
