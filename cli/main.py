"""The ``mech`` command line: list, show, solve, check (the contract in CONTRACT.md).

Everything a command prints is computed first and printed last, so a failure
never leaves a half-printed table; usage errors are one line on stderr with
exit status 2.
"""

from __future__ import annotations

import errno
import gc
import json
import os
import re
import sys
import time

import click

from mech.cli.options import collect_params
from mech.problems.values import parse_rtol
from mech.core.errors import BadInput, BadUsage
from mech.core.exits import EXIT_DISAGREE, EXIT_INTERNAL, EXIT_INTERRUPTED, EXIT_OK, EXIT_USAGE, internal_error
_STARTED = time.monotonic()  # the command's start (this module loads first): a solve's budget counts from here


class UsageFailure(click.ClickException):
    exit_code = EXIT_USAGE


def _get(ex_id: str):
    import mech

    try:
        return mech.exercise(ex_id)
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None


def _complete_ids(ctx, param, incomplete):
    import mech

    return [e.id for e in mech.exercises() if e.id.startswith(incomplete)]


def _complete_outputs(ctx, param, incomplete):
    """``--expect th<TAB>`` -> ``theta_c=``: the outputs of the exercise already named on the line."""
    import mech

    ex_id = ctx.params.get("ex_id") or ctx.meta.get("mech_exercise_id")
    try:
        ex = mech.exercise(ex_id) if ex_id else None
    except BadInput:
        ex = None
    if ex is None:
        return []
    from click.shell_completion import CompletionItem

    name = incomplete.split("=", 1)[0]
    if "=" in incomplete:
        return []
    return [CompletionItem(f"{o.name}=", help=f"[{o.unit}] {o.doc}") for o in ex.outputs
            if o.name.startswith(name)]


def _emit_json(obj) -> None:
    click.echo(json.dumps(obj, indent=2, allow_nan=False))


class MechGroup(click.Group):
    """click's group, with every error made one line on stderr and never a traceback.

    Overriding ``main`` (rather than wrapping the console script) makes click's
    test runner see exactly what users see.
    """

    # commands kept in their own modules, imported only when called; their one-line summaries (the first
    # sentence of each command's help, tests/test_cli_first_hour.py holds them equal) are listed by
    # `mech --help` without importing them
    LAZY = {
        "assign": ("mech.cli.assign", "assign_cmd",
                   "Personal variants for a class: each student's parameters drawn, rounded and verified, with the key."),
        "bench": ("mech.cli.bench", "bench_cmd", "Speed against error of exercise ID's numeric solver."),
        "grade": ("mech.cli.grading", "grade_cmd",
                  "Hold a TOML file of answers against mech (each [[answer]]: exercise, params, expect, rtol)."),
        "plot": ("mech.cli.plot", "plot_cmd", "Draw exercise ID: its scene with analytic and numeric results overlaid."),
        "sweep": ("mech.cli.sweep", "sweep_cmd",
                  "Solve exercise ID over a range: --NAME START:STOP:N[:log] for each swept parameter."),
    }

    def _lazy(self, name):
        import importlib

        module_name, attr, _summary = self.LAZY[name]
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:
            if exc.name == module_name:
                return None
            raise
        return getattr(module, attr)

    def list_commands(self, ctx):
        return sorted(set(super().list_commands(ctx)) | set(self.LAZY))

    def get_command(self, ctx, name):
        cmd = super().get_command(ctx, name)
        if cmd is None and name in self.LAZY:
            cmd = self._lazy(name)
        return cmd

    def format_commands(self, ctx, formatter):
        """The command list of ``mech --help``, as click lays it out, the lazy commands from their summaries."""
        names = self.list_commands(ctx)
        limit = formatter.width - 6 - max(len(n) for n in names)
        rows = []
        for name in names:
            if name in self.LAZY:
                rows.append((name, _shorten(self.LAZY[name][2], limit)))
            else:
                cmd = super().get_command(ctx, name)
                if cmd is not None and not cmd.hidden:
                    rows.append((name, cmd.get_short_help_str(limit)))
        with formatter.section("Commands"):
            formatter.write_dl(rows)

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        code = EXIT_OK
        try:
            _environment_checks()
            rv = super().main(args=args, prog_name=prog_name or "mech", complete_var=complete_var,
                              standalone_mode=False, **extra)
            code = rv if isinstance(rv, int) else EXIT_OK
            _flush_stdout()
        except click.exceptions.Exit as exc:
            code = exc.exit_code
            try:
                _flush_stdout()
            except OSError as err:
                code = _stdout_failed(err)
        except click.ClickException as exc:
            _error(exc.format_message())
            code = EXIT_USAGE if isinstance(exc, (click.UsageError, UsageFailure)) else exc.exit_code
        except (BadUsage, BadInput) as exc:  # bad input found below the command's own checks: exit 2, one line
            _error(str(exc))
            code = EXIT_USAGE
        except click.Abort:
            click.echo("mech: aborted", err=True)
            code = EXIT_INTERRUPTED
        except BrokenPipeError:
            _quiet_stdout()
            code = EXIT_OK
        except SystemExit as exc:
            # click answers a closed pipe (``mech list | head -c0``) with sys.exit(1) after pacifying
            # standard output: the reader stopped early, which is not a failure
            from click.utils import PacifyFlushWrapper

            if not isinstance(sys.stdout, PacifyFlushWrapper):
                raise
            _quiet_stdout()
            code = EXIT_OK if exc.code in (0, 1, None) else exc.code
        except UnicodeEncodeError as exc:
            _quiet_stdout()
            bad = exc.object[exc.start:exc.end] if isinstance(exc.object, str) else "?"
            _error(f"standard output cannot show {ascii(bad)} in its encoding ({exc.encoding}): set "
                   "PYTHONIOENCODING=utf-8, or use --json")
            code = EXIT_USAGE
        except OSError as exc:
            import errno

            # files mech writes report their own failures (BadInput); what is left is standard output
            if _stdout_broken() or exc.errno in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG, errno.EIO, errno.EBADF):
                code = _stdout_failed(exc)
            else:
                _error(internal_error(exc))
                code = EXIT_INTERNAL
        except RecursionError:
            _error("input nested too deeply")
            code = EXIT_USAGE
        except MemoryError:  # the input asked for too much: one line, once the exception has let go of it
            code = _OUT_OF_MEMORY
        except Exception as exc:  # a defect: say so in one line, never a traceback
            if _from_memory(exc):
                code = _OUT_OF_MEMORY
            else:
                _error(internal_error(exc))
                code = EXIT_INTERNAL
        if code is _OUT_OF_MEMORY:
            _out_of_memory()
            code = EXIT_USAGE
        if standalone_mode:
            sys.exit(code)
        return code


def _environment_checks() -> None:
    """What the environment must give before a command runs: an open standard output, a usable
    ``MECH_BUDGET_S``; ``COLUMNS`` read as the tables read it (below 60 as 60, zero or garbage unset)."""
    from mech.core.safeio import budget_seconds, normalize_columns

    normalize_columns()
    if sys.stdout is None:
        raise UsageFailure("standard output is closed: nothing could be reported (redirect it to a file "
                           "or /dev/null)")
    budget_seconds()


_OUT_OF_MEMORY = object()  # ``main``'s mark for an input that asked for more memory than there is
_OOM_LINE = (b"mech: error: out of memory: the input asks for more than this machine gives "
             b"(fewer points, entries or values)\n")


def _from_memory(exc: BaseException) -> bool:
    """An exception that is a lack of memory under another name: a C extension's SystemError over a
    MemoryError, an OSError ENOMEM, a module that could not be mapped in (ImportError)."""
    for _ in range(8):  # the exception, and what it was raised from or during
        if exc is None:
            return False
        if isinstance(exc, MemoryError) or (isinstance(exc, OSError) and exc.errno == errno.ENOMEM):
            return True
        if isinstance(exc, ImportError) and ("failed to map segment" in str(exc)
                                             or "Cannot allocate memory" in str(exc)):
            return True
        exc = exc.__cause__ or exc.__context__
    return False


def _out_of_memory() -> None:
    """The one line, written with what is already allocated (an import could fail here)."""
    try:
        gc.collect()
    except MemoryError:
        pass
    try:
        os.write(2, _OOM_LINE)
    except (OSError, MemoryError):
        pass


def _error(text: str) -> None:
    from mech.core.safeio import escape

    line = escape(_one_line(text))
    if len(line) > 2000:
        line = line[:2000] + "..."
    click.echo(f"mech: error: {line}" if not line.startswith("internal error") else f"mech: {line}", err=True)


def _flush_stdout() -> None:
    if sys.stdout is not None:
        sys.stdout.flush()


def _stdout_broken() -> bool:
    try:
        _flush_stdout()
    except (OSError, ValueError):
        return True
    return False


def _quiet_stdout() -> None:
    """Point standard output at /dev/null, so that the interpreter's last flush finds nothing to fail on."""
    import os

    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError, AttributeError):
        pass


def _stdout_failed(exc: OSError) -> int:
    _quiet_stdout()
    _error(f"cannot write to standard output: {exc.strerror or exc}")
    return EXIT_USAGE


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
@click.option("--json", "as_json", is_flag=True, help="Print a JSON array instead of a table.")
def list_cmd(chapter, as_json):
    """List the registered exercises: id, title, topic, and whether the analytic values are exact.

    A mark (†) flags the exercises set for mech on the chapter's topics; the others are the book's own.
    """
    import mech

    exercises = mech.exercises(int(chapter) if chapter else None)
    if as_json:
        _emit_json([{"id": e.id, "title": e.title, "topic": e.topic, "methods": list(e.methods),
                     "theory": e.theory, "from_book": e.from_book} for e in exercises])
    else:
        from mech.cli import listing

        listing.print_list(exercises)


@cli.command("show")
@click.argument("ex_id", metavar="ID", shell_complete=_complete_ids)
@click.option("--json", "as_json", is_flag=True,
              help="Print one JSON object with the exercise's fields instead (fields: docs/json.md).")
@click.option("--derive", "derive", is_flag=True,
              help="Show the declared physics (Lagrangian or bodies and loads, forces, constraints) and the "
                   "equations of motion sympy derives from it (needs the 'derive' extra; docs/derive.md).")
@click.option("--latex", is_flag=True, help="With --derive: print the expressions as LaTeX.")
def show_cmd(ex_id, as_json, derive, latex):
    """Show an exercise: statement, parameters, outputs, formulas, numeric route, hard cases."""
    if latex and not derive:
        raise UsageFailure("--latex goes with --derive (mech show ID --derive --latex)")
    ex = _get(ex_id)
    if derive:
        from mech.cli import listing

        listing.print_derivation(ex, latex=latex, as_json=as_json)
    elif as_json:
        _emit_json({**ex.as_json(), "from_book": ex.from_book})
    else:
        from mech import render

        render.print_show(ex, from_book=ex.from_book)


def _takes_value(param) -> bool:
    return isinstance(param, click.Option) and not param.is_flag and not param.count


def _quote_hint(flag: str, value: str, extra: str) -> str:
    return (f"unexpected '{extra}' after {flag} {value}: a value with a space needs quotes "
            f"({flag} '{value} {extra}') or none ({flag} {value}{extra})")


class SolveCommand(click.Command):
    """Takes ``--NAME VALUE`` for the exercise's own parameters before click parses the rest.

    The value is taken whole, so ``--phi0 -pi/3`` is not mistaken for the ``-p`` option.  The slips a
    new user makes with it (``--l 67 m`` unquoted, ``-p theta0 60deg``, ``--theta0 --l 2``) get a
    one-line hint instead of click's "unexpected extra argument".  ``mech solve ID --help`` lists the
    parameters of exercise ID, and ``mech solve ID --<TAB>`` completes them.
    """

    def parse_args(self, ctx, args):
        params = self.get_params(ctx)
        known = {opt for p in params for opt in getattr(p, "opts", []) + getattr(p, "secondary_opts", [])}
        valued = {opt for p in params if _takes_value(p) for opt in p.opts + p.secondary_opts}
        short_valued = {o for o in valued if len(o) == 2 and o[0] == "-" and o[1] != "-"}
        # options that take NAME=VALUE (-p, and any other whose metavar says so)
        pairs = {opt: p.metavar for p in params if _takes_value(p) and "=" in (p.metavar or "") for opt in p.opts}
        lenient = ctx.resilient_parsing
        own, rest = [], []
        positionals = 0
        last = None  # (flag, value) of the last option that took a value, for the hint on a stray word
        i = 0
        while i < len(args):
            arg = args[i]
            if arg == "--":
                rest.extend(args[i:])
                break
            name = arg.split("=", 1)[0]
            if arg.startswith("--") and len(arg) > 2 and name not in known:
                own.append(arg)
                if "=" in arg:
                    last = tuple(arg.split("=", 1))
                elif i + 1 < len(args):
                    value = args[i + 1]
                    if re.match(r"--[A-Za-z]", value) and not lenient:
                        raise click.UsageError(f"{arg[2:].replace('-', '_')}: no value given before '{value}'; "
                                               f"write {arg} VALUE")
                    own.append(value)
                    last = (arg, value)
                    i += 1
            elif name in valued or (arg[:2] in short_valued and len(arg) > 2):
                rest.append(arg)
                if arg in valued and i + 1 < len(args):
                    value = args[i + 1]
                    if arg in pairs and "=" not in value and not lenient:
                        after = args[i + 2] if i + 2 < len(args) and not args[i + 2].startswith("-") else "VALUE"
                        raise click.UsageError(f"{arg} takes {pairs[arg]}: write {arg} {value}={after}")
                    rest.append(value)
                    last = (arg, value)
                    i += 1
                else:
                    last = tuple(arg.split("=", 1)) if "=" in arg else (arg[:2], arg[2:])
            elif arg.startswith("-") and len(arg) > 1:
                rest.append(arg)
            else:
                positionals += 1
                if positionals == 1:
                    ctx.meta["mech_exercise_id"] = arg
                elif not lenient and self._too_many(positionals):
                    if last is not None:
                        raise click.UsageError(_quote_hint(last[0], last[1], arg))
                    raise click.UsageError(f"unexpected '{arg}': give one exercise id, then --NAME VALUE pairs")
                rest.append(arg)
            i += 1
        ctx.meta["mech_param_args"] = own
        return super().parse_args(ctx, rest)

    def _too_many(self, positionals: int) -> bool:
        slots = sum(p.nargs if p.nargs > 0 else 10**9 for p in self.params if isinstance(p, click.Argument))
        return positionals > slots

    def format_help(self, ctx, formatter):
        super().format_help(ctx, formatter)
        ex_id = ctx.meta.get("mech_exercise_id")
        if ex_id is None:
            with formatter.section("Parameters"):
                formatter.write_text(f"mech {self.name} ID --help lists the parameters of exercise ID.")
            return
        try:
            ex = _get(ex_id)
        except UsageFailure as exc:
            with formatter.section("Parameters"):
                formatter.write_text(str(exc))
            return
        rows = []
        metavar = "RANGE" if self.name == "sweep" else "VALUE"  # mech sweep shares this parsing
        for p in ex.params:
            unit = "" if p.unit == "1" else f" [{p.unit}]"
            rows.append((f"--{p.name} {metavar}",
                         f"{p.symbol or p.name}{unit}: {p.doc}; default {p.show(p.default)}, "
                         f"allowed {p.range_text()}"))
        with formatter.section(f"Parameters of {ex.id} ({ex.title})"):
            formatter.write_dl(rows)

    def shell_complete(self, ctx, incomplete):
        from click.shell_completion import CompletionItem

        items = super().shell_complete(ctx, incomplete)
        ex_id = ctx.params.get("ex_id") or ctx.meta.get("mech_exercise_id")
        if ex_id and incomplete.startswith("-"):
            try:
                ex = _get(ex_id)
            except UsageFailure:
                return items
            given = {a[2:].split("=", 1)[0].replace("-", "_") for a in ctx.meta.get("mech_param_args", [])}
            own = [CompletionItem(f"--{p.name}", help=f"{p.doc}; default {p.show(p.default)}")
                   for p in ex.params if f"--{p.name}".startswith(incomplete) and p.name not in given]
            items = own + items
        return items


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
@click.option("--json", "as_json", is_flag=True,
              help="Print the result as one JSON object on stdout (fields: docs/json.md).")
@click.option("--expect", "expects", multiple=True, metavar="NAME=VALUE", shell_complete=_complete_outputs,
              help="Your answer for an output, judged to the digits written (repeatable): --expect theta_c=35.26deg.")
@click.option("--expect-rtol", "expect_rtol", metavar="R", help="Judge --expect values to this relative tolerance.")
@click.option("--expect-points", "expect_points", metavar="N",
              help="A formula in --expect is checked at N parameter sets drawn across the range [24].")
@click.option("--expect-seed", "expect_seed", metavar="S", help="Seed of those draws [fixed: verdicts repeat].")
@click.option("--min-digits", "min_digits", metavar="D",
              help="An --expect number with fewer significant digits is judged as if written to D [2].")
@click.option("--trajectory", "trajectory_file", metavar="FILE.csv",
              help="Write the integrated motion: t [s] and each state [unit], one row per time.")
@click.pass_context
def solve_cmd(ctx, ex_id, pairs, method, rtol_text, no_verify, as_json, expects, expect_rtol, expect_points,
              expect_seed, min_digits, trajectory_file):
    """Solve exercise ID; parameters as --NAME VALUE or -p NAME=VALUE.

    Values are SI unless a unit is given: 90deg, 15 cm, 2Hz, 100 rpm, pi/3.
    Exit status: 0 agree, 1 a cross-check failed (or an --expect value is off), 2 bad input.
    """
    ex = _get(ex_id)
    if trajectory_file and not ex.states:
        raise UsageFailure(f"--trajectory: the numeric route of {ex.id} follows no motion of the scene in time "
                           "(a quadrature, an eigenproblem or a root search, or integrations that are not the "
                           "motion: one-period maps, fundamental solutions, a radial profile): no trajectory")
    if trajectory_file and method == "analytic":
        raise UsageFailure("--trajectory needs the numeric method: drop --method analytic")
    if trajectory_file is not None:
        _check_output(trajectory_file, "--trajectory")
    from mech import api

    try:
        given = collect_params(ex, ctx.meta.get("mech_param_args", []), list(pairs))
        params = ex.resolve(given)
        rtol = parse_rtol(rtol_text, ex)
        expectations = None
        if expects or expect_rtol is not None:
            expectations = api.parse_expectations(ex, list(expects), expect_rtol, expect_points, expect_seed,
                                                  min_digits=min_digits)
        elif min_digits is not None:
            raise BadInput("--min-digits: given without any --expect NAME=VALUE")
        elif expect_points is not None or expect_seed is not None:
            raise BadInput("--expect-points/--expect-seed: given without any --expect NAME=FORMULA")
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None
    methods = ("analytic", "numeric") if method == "both" else (method,)
    verify = not no_verify and method != "analytic"
    sol = api.solve_resolved(ex, params, methods=methods, rtol=rtol, verify=verify, expectations=expectations,
                             budget_s=_solve_budget())
    if trajectory_file:  # the numeric solve's motion
        failed = sol.solver_failed
        try:
            trajectory = None if failed else sol.trajectory
        except Exception as exc:  # the motion's own solve ran out: said, never a traceback
            trajectory, failed = None, True
            click.echo(f"mech: trajectory: {' '.join(str(exc).split())}", err=True)
        if trajectory is None:
            why = "did not finish" if failed else "followed no motion at these parameters (nothing moves, or the " \
                "motion it integrates does not exist here)"
            click.echo(f"mech: no trajectory written: the numeric solve of {ex.id} {why}", err=True)
        else:
            try:
                trajectory.to_csv(trajectory_file)
            except BadInput as exc:
                raise UsageFailure(str(exc)) from None
    if as_json:
        _emit_json(sol.to_dict())
    else:
        from mech import render

        render.print_solve(sol)
    ctx.exit(EXIT_DISAGREE if sol.agree is False or sol.expect_ok is False else EXIT_OK)


@cli.command("check")
@click.argument("ids", nargs=-1, metavar="[ID]...", shell_complete=_complete_ids)
@click.option("--hard", is_flag=True, help="Also run every exercise's hard cases.")
@click.option("--json", "as_json", is_flag=True, help="Print a JSON report on stdout instead of the table.")
@click.option("--junit", "junit_file", metavar="FILE", help="Write a JUnit XML report.")
@click.option("--save-baseline", "save_baseline", metavar="FILE", help="Record every checked value with its error bar.")
@click.option("--baseline", "baseline_file", metavar="FILE", help="Fail when a value moved beyond its error bars since FILE.")
@click.option("-j", "--jobs", type=click.IntRange(1, 256),
              help="Processes to run the cases in [one per core from 8 cases on].")
@click.pass_context
def check_cmd(ctx, ids, hard, as_json, junit_file, save_baseline, baseline_file, jobs):
    """Cross-check every (or the named) exercise at its defaults, and with --hard its hard cases.

    Exit status 1 when any case fails: the CI regression command.
    """
    from mech import api
    from mech.cli.checking import progress_bar, write_junit

    for i in ids:
        _get(i)  # an unknown id: exit 2 before anything runs
    for path, what in ((junit_file, "--junit"), (save_baseline, "--save-baseline")):
        if path is not None:  # before the minutes of the check, not after
            _check_output(path, what)
    from mech.cli.checking import check_apart

    check_apart([(junit_file, "--junit"), (save_baseline, "--save-baseline")], [(baseline_file, "--baseline")])
    try:
        with progress_bar(not as_json) as bar:
            report, moved = api.check_against_baselines(list(ids) or None, hard, baseline=baseline_file,
                                                        save_baseline=save_baseline, jobs=jobs,
                                                        started=bar.started, finished=bar.finished)
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None
    if junit_file:
        write_junit(report, junit_file)
        if moved:
            from mech.cli.baseline import junit_baseline

            junit_baseline(junit_file, moved)
    if as_json:
        _emit_json({**report.as_json(), **({"baseline": moved.as_json()} if moved else {})})
    else:
        from mech import render

        render.print_check(report)
        if baseline_file or save_baseline:
            from mech.cli.baseline import print_baseline

            print_baseline(moved, save_baseline)
    ctx.exit(EXIT_OK if report.ok and (moved is None or moved.ok) else EXIT_DISAGREE)


def _solve_budget() -> float:
    """The solve's budget, counted from the command's start: MECH_BUDGET_S (8 s) covers the imports and
    the analytic side too, so that a budget stop ends the command near 8 s, not 8.5 s after it began."""
    from mech.core.safeio import budget_seconds

    full = budget_seconds()
    return max(0.5 * full, full - (time.monotonic() - _STARTED))


def _check_output(path, what: str) -> None:
    from mech.core.safeio import check_output

    try:
        check_output(path, what)
    except BadInput as exc:
        raise UsageFailure(str(exc)) from None


def main(argv=None) -> None:
    """Console-script entry point.  Leaves without the interpreter's teardown of numpy and scipy (0.3 s
    on a loaded 2-core machine, after the answer is out): the streams are flushed here, and the only
    processes mech starts die with it."""
    import os

    code = cli.main(args=argv, prog_name="mech", standalone_mode=False)
    for stream in (sys.stdout, sys.stderr):
        try:
            if stream is not None:
                stream.flush()
        except (OSError, ValueError):
            pass
    os._exit(code if isinstance(code, int) else EXIT_OK)


def _shorten(text: str, limit: int) -> str:
    """``text`` cut at a word to at most ``limit`` characters, "..." marking the cut."""
    if len(text) <= limit:
        return text
    words, out = text.split(), ""
    for w in words:
        if len(out) + len(w) + (1 if out else 0) > limit - 3:
            break
        out += (" " if out else "") + w
    return out + "..."


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


if __name__ == "__main__":  # pragma: no cover
    main()
