"""``mech plot``: the figure a student would draw to understand an exercise's answer."""

from __future__ import annotations

import click

from mech.cli.main import SolveCommand, UsageFailure, _complete_ids, _get
from mech.cli.options import collect_params
from mech.problems.values import param_name, parse_rtol
from mech.core.errors import BadInput, NumericFailure

FIGURE_BUDGETS = 2


@click.command("plot", cls=SolveCommand)
@click.argument("ex_id", metavar="ID", shell_complete=_complete_ids)
@click.option("-p", "pairs", multiple=True, metavar="NAME=VALUE", help="Set a parameter (repeatable).")
@click.option("-o", "--output", "out", type=click.Path(dir_okay=False), metavar="FILE",
              help="The file to write; .png, .svg or .pdf by its suffix  [default: mech-ID.png]")
@click.option("--generic", is_flag=True, help="The outputs against one parameter, even where a scene figure exists.")
@click.option("--vary", metavar="NAME", help="The parameter of the generic figure [the most telling one].")
@click.option("--points", "n_numeric", type=click.IntRange(0, 50), default=5, show_default=True,
              help="Numeric solves for the markers (each costs 0.05-1 s); 0: analytic lines only.")
@click.option("--rtol", "rtol_text", metavar="R", help="Requested accuracy of the numeric solver [exercise default].")
@click.option("--dpi", type=click.FloatRange(20, 600), default=110, show_default=True, help="Resolution of a PNG.")
@click.pass_context
def plot_cmd(ctx, ex_id, pairs, out, generic, vary, n_numeric, rtol_text, dpi):
    """Draw exercise ID: its scene with analytic and numeric results overlaid.

    \b
    Scenes, each computed by the exercise's own physics: the wall's force on
    the sliding ladder (4.15), Omega(l) with its optimum (4.10), the chime's
    normal modes (4.12), the heavy top's effective potential (4.21), the
    rotating frame's potential with the Lagrange points (4.27, 4.28), the
    pendulum's phase portrait (5.6), the Mathieu zone (5.11), the Kapitza
    chart (5.13).  Every exercise has the generic figure (--generic): each
    output against one parameter, analytic as a line, numeric as markers.
    \b
    Examples:
      mech plot 4.15 --theta0 80deg -o ladder.svg
      mech plot 4.1 --generic --vary R
    Matplotlib comes with the plot extra; in mech's checkout:
    pip install -e '.[plot]'.
    """
    from mech import api

    ex = _get(ex_id)
    try:
        given = collect_params(ex, ctx.meta.get("mech_param_args", []), list(pairs))
        params = ex.resolve(given)
        rtol = parse_rtol(rtol_text, ex)
        if vary:
            vary = param_name(ex, vary)
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None
    if out is not None and not out.strip():
        raise UsageFailure("-o/--output: an empty file name; give a file to write, or leave it out for "
                           f"mech-{ex.id}.png")
    out = out or f"mech-{ex.id}.png"
    try:
        api.plot_resolved(ex, params, out, generic=generic, vary=vary, n_numeric=n_numeric, rtol=rtol, dpi=dpi,
                          budgets=FIGURE_BUDGETS)
    except NumericFailure as exc:
        raise click.ClickException(f"cannot draw {ex.id}: {exc}") from None
    click.echo(f"wrote {out}", err=True)
