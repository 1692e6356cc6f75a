"""The ``mech`` command line: list, show, solve, check (the contract in CONTRACT.md).

Everything a command prints is computed first and printed last, so a failure
never leaves a half-printed table; usage errors are one line on stderr with
exit status 2.
"""

from __future__ import annotations

import json
import sys

import click

from mech.cli.options import collect_params, parse_rtol
from mech.problems.spec import BadInput

EXIT_OK, EXIT_DISAGREE, EXIT_USAGE = 0, 1, 2


class UsageFailure(click.ClickException):
    exit_code = EXIT_USAGE


def _registry():
    from mech.problems import registry

    return registry


def _get(ex_id: str):
    try:
        return _registry().get(ex_id)
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None


def _complete_ids(ctx, param, incomplete):
    return [e.id for e in _registry().index() if e.id.startswith(incomplete)]


def _emit_json(obj) -> None:
    click.echo(json.dumps(obj, indent=2, allow_nan=False))


class MechGroup(click.Group):
    """click's group, with every error made one line on stderr and never a traceback.

    Overriding ``main`` (rather than wrapping the console script) makes click's
    test runner see exactly what users see.
    """

    # commands kept in their own modules, imported only when listed or called
    LAZY = {
        "bench": ("mech.cli.bench", "bench_cmd"),
        "plot": ("mech.cli.plot", "plot_cmd"),
        "sweep": ("mech.cli.sweep", "sweep_cmd"),
    }

    def _lazy(self, name):
        import importlib

        module_name, attr = self.LAZY[name]
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:
            if exc.name == module_name:
                return None
            raise
        return getattr(module, attr)

    def list_commands(self, ctx):
        names = set(super().list_commands(ctx))
        names.update(n for n in self.LAZY if self._lazy(n) is not None)
        return sorted(names)

    def get_command(self, ctx, name):
        cmd = super().get_command(ctx, name)
        if cmd is None and name in self.LAZY:
            cmd = self._lazy(name)
        return cmd

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        code = EXIT_OK
        try:
            rv = super().main(args=args, prog_name=prog_name or "mech", complete_var=complete_var,
                              standalone_mode=False, **extra)
            code = rv if isinstance(rv, int) else EXIT_OK
        except click.exceptions.Exit as exc:
            code = exc.exit_code
        except click.ClickException as exc:
            click.echo(f"mech: error: {_one_line(exc.format_message())}", err=True)
            code = EXIT_USAGE if isinstance(exc, (click.UsageError, UsageFailure)) else exc.exit_code
        except click.Abort:
            click.echo("mech: aborted", err=True)
            code = 130
        except BrokenPipeError:
            code = EXIT_OK
        except Exception as exc:  # a defect: say so in one line, never a traceback
            click.echo(f"mech: internal error: {type(exc).__name__}: {_one_line(str(exc))}", err=True)
            code = EXIT_DISAGREE
        if standalone_mode:
            sys.exit(code)
        return code


@click.group(cls=MechGroup, context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100})
@click.version_option(package_name="mech-likharev", prog_name="mech", message="%(prog)s %(version)s")
def cli():
    """Solve the exercises of Likharev's Classical Mechanics, chapters 4 and 5, two ways.

    Every exercise has an analytic solution (derived) and an independent numeric
    one (from the equations of motion, energies or mass distributions); `mech solve`
    shows both and checks that they agree.

    \b
    Examples:
      mech list --chapter 4
      mech show 4.15
      mech solve 4.15 --theta0 60deg
      mech solve 4.10 -p l=15cm --json
      mech check --hard
    """


@cli.command("list")
@click.option("--chapter", type=click.Choice(["4", "5"]), help="Only this chapter's exercises.")
@click.option("--json", "as_json", is_flag=True, help="A JSON array instead of a table.")
def list_cmd(chapter, as_json):
    """List the registered exercises: id, title, topic, methods."""
    exercises = [e for e in _registry().index() if not chapter or e.chapter == int(chapter)]
    if as_json:
        _emit_json([{"id": e.id, "title": e.title, "topic": e.topic, "methods": list(e.methods)} for e in exercises])
    else:
        from mech.cli import listing

        listing.print_list(exercises)


@cli.command("show")
@click.argument("ex_id", metavar="ID", shell_complete=_complete_ids)
@click.option("--json", "as_json", is_flag=True, help="One JSON object with the catalogue's fields.")
def show_cmd(ex_id, as_json):
    """Show an exercise: statement, parameters, outputs, formulas, numeric route, hard cases."""
    ex = _get(ex_id)
    if as_json:
        _emit_json(ex.as_json())
    else:
        from mech.cli import render

        render.print_show(ex)


class SolveCommand(click.Command):
    """Takes ``--NAME VALUE`` for the exercise's own parameters before click parses the rest.

    The value is taken whole, so ``--phi0 -pi/3`` is not mistaken for the ``-p`` option.
    """

    def parse_args(self, ctx, args):
        known = {opt for p in self.get_params(ctx) for opt in getattr(p, "opts", []) + getattr(p, "secondary_opts", [])}
        own, rest = [], []
        i = 0
        while i < len(args):
            arg = args[i]
            if arg == "--":
                rest.extend(args[i:])
                break
            name = arg.split("=", 1)[0]
            if arg.startswith("--") and len(arg) > 2 and name not in known:
                own.append(arg)
                if "=" not in arg and i + 1 < len(args):
                    own.append(args[i + 1])
                    i += 1
            else:
                rest.append(arg)
            i += 1
        ctx.meta["mech_param_args"] = own
        return super().parse_args(ctx, rest)


@cli.command("solve", cls=SolveCommand)
@click.argument("ex_id", metavar="ID", shell_complete=_complete_ids)
@click.option("-p", "pairs", multiple=True, metavar="NAME=VALUE", help="Set a parameter (repeatable).")
@click.option(
    "--method",
    type=click.Choice(["both", "analytic", "numeric"]),
    default="both",
    show_default=True,
    help="Which solver(s) to run.",
)
@click.option("--rtol", "rtol_text", metavar="R", help="Requested accuracy of the numeric solver [exercise default].")
@click.option("--no-verify", is_flag=True, help="Skip the rerun at rtol/10 that tests the numeric accuracy claim.")
@click.option("--json", "as_json", is_flag=True, help="The contract's JSON object on stdout.")
@click.pass_context
def solve_cmd(ctx, ex_id, pairs, method, rtol_text, no_verify, as_json):
    """Solve exercise ID; parameters as --NAME VALUE or -p NAME=VALUE.

    Values are SI unless a unit is given: 90deg, 15 cm, 2Hz, 100 rpm, pi/3.
    Exit status: 0 agree, 1 a cross-check failed, 2 bad input.
    """
    from mech.solvers.crosscheck import cross_check

    ex = _get(ex_id)
    try:
        given = collect_params(ex, ctx.meta.get("mech_param_args", []), list(pairs))
        params = ex.resolve(given)
        rtol = parse_rtol(rtol_text, ex)
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None
    methods = ("analytic", "numeric") if method == "both" else (method,)
    result = cross_check(ex, params, methods=methods, rtol=rtol, verify=not no_verify and method != "analytic")
    if as_json:
        _emit_json(result.as_json())
    else:
        from mech.cli import render

        render.print_solve(result)
    ctx.exit(EXIT_DISAGREE if result.agree is False else EXIT_OK)


@cli.command("check")
@click.argument("ids", nargs=-1, metavar="[ID]...", shell_complete=_complete_ids)
@click.option("--hard", is_flag=True, help="Also run every exercise's hard cases.")
@click.option("--json", "as_json", is_flag=True, help="A JSON report on stdout.")
@click.option("--junit", "junit_file", type=click.Path(dir_okay=False, writable=True), help="Write a JUnit XML report.")
@click.pass_context
def check_cmd(ctx, ids, hard, as_json, junit_file):
    """Cross-check every (or the named) exercise at its defaults, and with --hard its hard cases.

    Exit status 1 when any case fails: the CI regression command.
    """
    from mech.cli.checking import run_check, write_junit

    exercises = [_get(i) for i in ids] if ids else list(_registry().all_exercises().values())
    report = run_check(exercises, hard=hard, progress=not as_json)
    if junit_file:
        write_junit(report, junit_file)
    if as_json:
        _emit_json(report.as_json())
    else:
        from mech.cli import render

        render.print_check(report)
    ctx.exit(EXIT_OK if report.ok else EXIT_DISAGREE)


def main(argv=None) -> None:
    """Console-script entry point."""
    cli.main(args=argv, prog_name="mech")


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


if __name__ == "__main__":  # pragma: no cover
    main()
