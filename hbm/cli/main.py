"""Command line: ``python3 -m hbm`` (or ``frictiondamp``) runs the default case.

With no arguments it computes the frequency response of the built-in default case
(``hbm.cli.cases.default_case``) and writes ``frf.csv`` and ``frf.png`` to the current folder
(``--out DIR`` elsewhere), printing where they went and the peak.  Subcommands are registered
in ``COMMANDS``: ``default`` (the same job, named), ``run SCENE.toml`` (``docs/scenes.md``; exit
code 0 on success, 1 on a failed computation, 2 on an invalid scene, 130 on Ctrl-C, 143 on
SIGTERM, each saying what was kept; a scene with a ``[study]`` table runs as a study, ``hbm.study``),
``new SCENE.toml`` (an annotated template scene), ``models`` and ``keys`` (listings generated
from the registries and the schema).
"""

from __future__ import annotations

import argparse
import errno
import math
import os
import signal
import sys
import tempfile
import time
import warnings
from pathlib import Path
from typing import Any, Callable

import numpy as np

from contact_models import __version__
from contact_models.accuracy import AccuracyWarning

from .._validation import MIN_RELATIVE_TOL, InputError
from ..frf import DEFAULT_TOL, MODELS, PRESETS, frequency_response, may_climb
from ..balance.presets import MAX_RTOL
from ..output import COMMENT
from .cases import default_case
from .figure import job_figure

__all__ = ["main", "build_parser", "program_name", "study_lines", "accuracy_line", "warning_line",
           "COMMANDS",
           "DESCRIPTION", "EXAMPLES",
           "Terminated"]

#: The main job's ``--model``: the physical curve, the bar with every mode wherever the single-mode bar
#: is further than its share of tol from it.
DEFAULT_MODEL = "auto"
#: The first line of ``--help``.
DESCRIPTION = ("Forced response of friction-damped structures (harmonic balance, continuation): with no "
               "command the main job, a blade with a microslip damper; run SCENE.toml for your own.")
#: Examples shown at the end of ``--help``.
EXAMPLES = """examples:
  {prog}                                   the main job (the default case): frf.csv and frf.png here
  {prog} --out results                     the same, written to results/
  {prog} run study.toml                    run a scene (a study described in a TOML file)
  {prog} run study.toml --check            validate it and print its effects; compute nothing
  {prog} run study.toml --set sweep.tol=fast --out quick
  {prog} run chart.toml --workers 2        a scene with [study]: its runs on 2 processes
  {prog} run chart.toml --scheduler tcp://host:8786   ... on a running Dask cluster
  {prog} new study.toml                    write an annotated template scene that runs as written
  {prog} models                            the damper models a scene can name
  {prog} keys                              every key of a scene, with its default and meaning"""


def _default(args: argparse.Namespace) -> int:
    out = Path(args.out if args.out is not None else ".")
    names = ("frf.csv", "frf.png")
    _check_folder(out, names, "--out" if args.out is not None else "the current folder")
    written: list[Path] = []

    def kept():  # the files this job wrote (the curve is written before the figure is drawn)
        return f"kept files: {', '.join(str(p.resolve()) for p in written) or 'none'}"

    from .progress import ProgressLine, ticking  # lazily, as in _run

    line = ProgressLine(sys.stderr, enabled=True, plain=not sys.stderr.isatty())
    what = f"the main job (--model {getattr(args, 'model', None) or DEFAULT_MODEL})"
    return _compute(line, lambda: ticking(line, what, lambda state: _default_job(args, out, written, state)), kept,
                    lambda job: job[1], code=lambda job: job[0])


def _default_job(args: argparse.Namespace, out: Path, written: list, state: Any = None) -> tuple[int, list]:
    """The main job: ``(exit code, lines to print)``; ``written`` collects the files as they are written,
    ``state`` (``hbm.cli.progress.Elapsed``) the points as the solve accepts them."""
    case = default_case()
    t0 = time.perf_counter()
    model = getattr(args, "model", None) or DEFAULT_MODEL
    legacy = {} if args.rtol is None else {"rtol": args.rtol}  # --rtol: an earlier release's option, still read

    def accepted(point):  # the progress line's count (with a refined model the points come at the end)
        if state is not None:
            state.points, state.omega = state.points + 1, point.omega

    with warnings.catch_warnings(record=True) as caught:  # said after the files are written, one line each
        warnings.simplefilter("always", AccuracyWarning)
        warnings.filterwarnings("ignore", category=DeprecationWarning)
        frf = frequency_response(case.blade, case.element, omega_range=case.omega_range, tol=_tol(args),
                                 model=model, callback=accepted, **legacy)
    if len(frf) == 0:
        raise ComputationFailed(f"no point of the frequency response converged: {frf.message}")
    pk = frf.peak()
    out.mkdir(parents=True, exist_ok=True)
    elapsed = time.perf_counter() - t0
    csv_path = frf.to_csv(out / "frf.csv", case=case.description)  # first: a signal during the figure keeps it
    written.append(csv_path)
    given = None if model == "given" else _single_mode_curve(frf, case, _tol(args))  # drawn beside the refined one
    png_path = job_figure(frf, case, out / "frf.png", given=given)
    written.append(png_path)
    for w in caught:  # the call's own warnings (for "peak": the given model's points outside the peak's window)
        warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
    a_min = case.element.slip_amplitude(pk.omega)
    in_a_min = f" (= {pk.amplitude / a_min:.4g} a_min)" if a_min > 0.0 else ""
    lines = [f"case: {case.description}",
             f"{len(frf)} points in {elapsed:.2f} s ({frf.nsteps} steps, {frf.nit} Newton iterations, "
             f"{frf.nfev} element evaluations): {frf.message}",
             f"peak: omega = {pk.omega:.9g} rad/s, amplitude = {pk.amplitude:.9g} m{in_a_min}",
             f"wrote {csv_path.resolve()}",
             f"wrote {png_path.resolve()}",
             accuracy_line(frf, pk, case.element, model)]
    return (0 if frf.success else 1), lines


def _single_mode_curve(frf: Any, case: Any, tol: float) -> Any:
    """The single-mode curve drawn beside a refined ``frf`` (its error in the legend): the whole range as
    ``frequency_response`` traced it first, with the element as given (``frf._work[0]``, ``hbm.adapt.along``), where
    that trace is the one a call with ``model="given"`` makes (the element as given, which keeps its H along the
    curve); else that call.  The two differ only in the estimate's peak part at the points beside the peak (the
    first trace's sampled peak there, the call's located one): the curve drawn is the same, and so is the legend's
    largest estimate wherever it lies away from those points (the default case's: 10 % at 38387 rad/s, 32 points
    below the peak)."""
    first = frf._work[0]
    if all(c.element is case.element for c in first.contacts) and not may_climb(first.contacts, False):
        return first
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        return frequency_response(case.blade, case.element, omega_range=case.omega_range, tol=tol)


class UsageError(InputError):
    """A bad command line or output place (exit code 2, nothing computed)."""


class ComputationFailed(RuntimeError):
    """The computation failed (exit code 1): its message says where and why."""


def _check_folder(folder: Path, names: Any, what: str) -> None:
    """Refuse, before anything is computed, an output ``folder`` that is a file, holds a folder
    where one of the output files ``names`` goes, or whose name no file system takes (``UsageError``)."""
    for path in [folder] + [folder / name for name in names]:
        try:
            os.stat(path)
        except OSError as exc:  # a name too long: the outputs could not be written after the run (the rest below)
            if exc.errno == errno.ENAMETOOLONG:
                raise UsageError(f"{what} = {folder}: {path} cannot be a file name here ({exc.strerror}) "
                                 "(nothing computed, nothing written)") from None
        except ValueError as exc:
            raise UsageError(f"{what} = {folder!r}: {exc} (nothing computed, nothing written)") from None
    if folder.exists() and not folder.is_dir():
        raise UsageError(f"{what} = {folder}: is a file, not a folder; give a folder for the outputs "
                         "(nothing computed, nothing written)")
    for name in names:
        if (folder / name).is_dir():
            raise UsageError(f"{folder / name} is a folder where the output file {name} goes; move it or give "
                             "--out another folder (nothing computed, nothing written)")
    place = folder.absolute()
    while not place.exists() and place != place.parent:  # the folder, or where it would be made
        place = place.parent
    if not place.is_dir():
        raise UsageError(f"{what} = {folder}: {place} is a file, so the folder cannot be made there "
                         "(nothing computed, nothing written)")
    try:  # a file made and removed at once: the place takes files (os.access cannot tell for root or /proc)
        with tempfile.TemporaryFile(dir=place):
            pass
    except OSError as exc:
        raise UsageError(f"{what} = {folder}: nothing can be written in {place} ({exc.strerror or exc}) "
                         "(nothing computed, nothing written)") from None


def accuracy_line(frf: Any, pk: Any, given: Any, model: str | None = None) -> str:
    """The main job's last line from the curve itself: the peak, its estimated error (``pk.estimate``) and
    the model.

    ``model`` is the job's ``--model``.  With "peak" the line names the model of the point the peak
    was located at (``frf.point_models``): the refined one where the peak's window was traced again,
    ``given``'s where its model source was within its share of tol there."""
    known = pk.estimate is not None and math.isfinite(pk.estimate)  # (None: nothing estimated at the peak)
    err = pk.estimate if known else float(frf.error_estimate[int(np.argmax(frf.amplitude))])
    models = set(np.asarray(frf.point_models).tolist()) if frf.point_models is not None else set()
    if model == "peak":
        i = _peak_point(frf, pk)
        err = pk.estimate if known else float(frf.error_estimate[i])
        at = str(frf.point_models[i]) if frf.point_models is not None else type(frf.element).__name__
        within = "within" if err <= frf.tol else "further than"
        if len(models) > 1:
            how = (f"{at}, the bar with every mode in the windows that hold the peak, where the single-mode "
                   f"{type(given).__name__} is further than its share of tol from it; {within} tol = {frf.tol:g}")
        else:
            how = f"{at}, {within} tol = {frf.tol:g}"
        return (f"peak {pk.omega:.6g} rad/s, {pk.amplitude:.4g} m, estimated error {100.0 * err:.2g} % "
                f"(model: {how}; the model and harmonics of each point are in the CSV)")
    if len(models) > 1:  # model="auto": the curve spliced from the models that answered where they do
        worst = float(np.max(frf.error_estimate))
        within = "within" if worst <= frf.tol else "above"
        return (f"peak {pk.omega:.6g} rad/s, {pk.amplitude:.4g} m, estimated error {100.0 * err:.2g} %; the whole "
                f"curve's largest estimated error {100.0 * worst:.2g} %, {within} tol = {frf.tol:g} (model: the bar "
                f"with every mode, AllModeMicroslip, where the single-mode {type(given).__name__} is further than "
                f"its share of tol from it; the model and harmonics of each point are in the CSV)")
    if frf.element is not given:
        model = (f"{type(frf.element).__name__}, the bar with every mode: the single-mode "
                 f"{type(given).__name__} is further than tol = {frf.tol:g} from it here")
    elif err > frf.tol:
        model = (f"{type(given).__name__}, further than tol = {frf.tol:g}; --model peak or auto (the default) "
                 "give the peak of the bar with every mode where it is")
    else:
        model = f"{type(given).__name__}, within tol = {frf.tol:g}"
    return (f"peak {pk.omega:.6g} rad/s, {pk.amplitude:.4g} m, estimated error {100.0 * err:.2g} % "
            f"(model: {model})")


def _peak_point(frf: Any, pk: Any) -> int:
    """The point of ``frf`` nearest its located peak ``pk`` (relative distance in omega and amplitude, so
    that a fold's other points at the same omega are not taken): the peak is located between the
    largest point and a neighbour, and the nearest of them is the one whose model is named there."""
    d = np.abs(frf.omega / pk.omega - 1.0) + np.abs(frf.amplitude / pk.amplitude - 1.0)
    return int(np.argmin(d))


def _run(args) -> int:
    # lazily, here and in the other subcommands: the main job reads no scene (40 ms of its start)
    from ..scenes import (SceneError, effect_lines, load_scene, output_names, parse_override, plan_scene,
                          run_scene, summary_lines)
    from .progress import ProgressLine

    try:
        overrides = dict(parse_override(text) for text in args.set)
        if args.rtol is not None:
            overrides["sweep.tolerance"] = args.rtol
        scene = load_scene(args.scene, overrides=overrides)
        options = (args.workers, args.scheduler, args.executor, args.time_limit)
        if scene.study is None and any(o is not None for o in options):
            raise SceneError([f"{scene.path}: --workers, --scheduler, --executor and --time-limit need a [study] "
                              "table (docs/studies.md)"])
        plan = plan_scene(scene) if scene.study is None else None
    except ValueError as exc:  # SceneError, or a check of the library on the scene's values: before computing
        print(f"error: invalid scene (nothing computed, nothing written):\n{exc}", file=sys.stderr)
        return 2
    if scene.study is not None:
        return _run_study(args, overrides)
    folder = Path(args.out if args.out is not None else scene.output["folder"])
    if not args.check:
        _check_folder(folder, output_names(scene).values(), "--out" if args.out is not None else "output.folder")
    if args.check:
        print(f"scene {scene.path} is valid: {len(plan.runs)} run(s)")
        print("\n".join(effect_lines(plan)))
        return 0
    line = ProgressLine(sys.stderr, enabled=not args.quiet, plain=not sys.stderr.isatty())

    def kept():  # counted on disk: the signal may come between a row's write and its progress call
        files = [folder / name for name in output_names(scene).values() if (folder / name).exists()]
        partial = folder / output_names(scene)["partial"]
        points = (sum(not t.startswith(COMMENT) for t in partial.read_text().splitlines()) - 1 if partial.exists()
                  else line.points)  # the rows: not the column names nor the "#" lines
        return f"kept {points} finished points; files: {', '.join(str(p) for p in files) or 'none'}"

    with warnings.catch_warnings(record=True) as caught:  # the runs' accuracy warnings, said once after the summary
        warnings.simplefilter("always", AccuracyWarning)
        code = _compute(line, lambda: run_scene(scene, args.out, plan=plan, progress=line), kept, summary_lines)
    _say_after(caught, args.quiet)
    return code


def warning_line(message: Any, category: type) -> str:
    """A warning as the command line prints it: ``warning: <message> (<category>)``, one line, no
    file path or source line (Python's own format names the library's line that warned)."""
    text = " ".join(str(message).split())
    return f"warning: {text} ({category.__name__})"


def _one_line(message, category, filename, lineno, line=None) -> str:
    """``warnings.formatwarning`` while the command line runs: :func:`warning_line`."""
    return warning_line(message, category) + "\n"


#: The arguments of ``frequency_response`` a warning's advice names, and the scene keys that set them.
SCENE_KEYS = (("model='auto'", 'effects.phase_differences = "on" (the bar with every mode over the whole curve)'),
              ("harmonics=", "effects.harmonics, which a scene fixes (default 1; above 1 only for a damper with a "
                             "time-domain law)"),
              ("AllModeMicroslip: cells", "the all-mode bar's cells are damper.cells"),
              ("n_t=", "effects.samples"),
              ("tol=", "sweep.tol"))


def in_scene_terms(message: str) -> str:
    """``message`` with the scene keys of the ``frequency_response`` arguments its advice names (a scene
    user sets keys, not arguments); unchanged where it names none."""
    said = [key if " are " in key else f"{argument} is {key}" for argument, key in SCENE_KEYS if argument in message]
    return f"{message} (in a scene: {'; '.join(said)})" if said else message


def _say_after(caught: list, quiet: bool) -> None:
    """The accuracy warnings ``caught`` during a scene or study, each said once after its summary
    (on stdout with it: stderr carries the progress line; ``summary.json`` records them too), with
    the scene keys of the arguments their advice names; any other warning shown as it would have been
    (one line on stderr)."""
    for w in {str(w.message): w for w in caught if issubclass(w.category, AccuracyWarning)}.values():
        if not quiet:
            print(warning_line(in_scene_terms(str(w.message)), w.category))
    for w in caught:
        if not issubclass(w.category, AccuracyWarning):
            warnings.showwarning(w.message, w.category, w.filename, w.lineno)


def _compute(line, compute, kept, report, code=lambda result: result.exit_code) -> int:
    """Run ``compute()`` behind the progress ``line``; print ``report(result)``, or after Ctrl-C or
    SIGTERM ``kept()`` (what is on disk).  Returns the exit code (``code(result)``)."""
    def interrupt_once(signum, frame):  # a second Ctrl-C must not cut the shutdown and its message short
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        raise KeyboardInterrupt

    previous = signal.signal(signal.SIGINT, interrupt_once)
    try:
        result = compute()
    except KeyboardInterrupt as exc:
        signal.signal(signal.SIGINT, signal.SIG_IGN)  # the process ends: say what was kept, once
        line.clear()
        print(f"{_stopped(exc)}: {kept()}", file=sys.stderr)
        return _interrupted_code(exc)
    except ImportError as exc:  # an optional extra not installed (Dask)
        line.clear()
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except OSError as exc:
        line.clear()
        print(f"error: cannot write the outputs: {exc}; {kept()}", file=sys.stderr)
        return 1
    except InputError:  # bad input found on the way (main says it, exit code 2)
        line.clear()
        raise
    except (ComputationFailed, ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
        line.clear()  # a failure inside the computation, not a bad input: said in one line, exit code 1
        print(f"error: the computation failed: {exc}; {kept()}", file=sys.stderr)
        return 1
    finally:
        if signal.getsignal(signal.SIGINT) is interrupt_once:
            signal.signal(signal.SIGINT, previous)
    line.clear()
    print("\n".join(report(result)))
    return code(result)


class Terminated(KeyboardInterrupt):
    """SIGTERM, raised like Ctrl-C so that a scene or study says what it kept (exit code 143)."""


def _terminate(signum, frame):
    raise Terminated()


def _stopped(exc: BaseException) -> str:
    return "terminated (SIGTERM)" if isinstance(exc, Terminated) else "interrupted"


def _interrupted_code(exc: BaseException) -> int:
    """130 after Ctrl-C, 143 after SIGTERM (128 + the signal's number, the shells' convention)."""
    return 143 if isinstance(exc, Terminated) else 130


def _run_study(args, overrides) -> int:
    from ..study import FILES, Study, check_scene, read_records, run_study  # lazily: as in _run
    from .progress import ProgressLine  # lazily: as in _run

    try:
        if args.check:  # makes no run's point but the first: the same time for any number of runs
            print("\n".join(check_scene(args.scene, overrides=overrides)))
            return 0
        study = Study.from_scene(args.scene, overrides=overrides)
    except ValueError as exc:  # SceneError, or a check of the library on the scene's values: before computing
        print(f"error: invalid scene (nothing computed, nothing written):\n{exc}", file=sys.stderr)
        return 2
    folder = Path(args.out if args.out is not None else study.settings["folder"])
    _check_folder(folder, [n for k, n in FILES.items() if k != "lock"], "--out" if args.out is not None
                  else "output.folder")
    line = ProgressLine(sys.stderr, enabled=not args.quiet, plain=not sys.stderr.isatty())

    def kept():
        files = [folder / FILES[k] for k in ("records", "partial") if (folder / FILES[k]).exists()]
        return (f"kept {len(read_records(folder / FILES['records']))} finished runs; files: "
                f"{', '.join(str(p) for p in files) or 'none'}; run the same command again to compute only the "
                "missing runs")

    with warnings.catch_warnings(record=True) as caught:  # the study's summary of its runs' warnings, after its own
        warnings.simplefilter("always", AccuracyWarning)
        code = _compute(line, lambda: run_study(study, folder, executor=args.executor, workers=args.workers,
                                                scheduler=args.scheduler, progress=line, time_limit=args.time_limit),
                        kept, study_lines)
    _say_after(caught, args.quiet)
    return code


def study_lines(result: Any) -> list:
    """The end-of-study summary of a :class:`hbm.study.StudyResult` as lines of text."""
    s = result.summary
    lines = [f"study: {s['title'] or 'untitled'}: {s['runs']} runs over {', '.join(s['parameters'])}",
             f"{s['succeeded']} succeeded, {s['failed']} failed, {s['not_computed']} not computed; "
             f"{s['computed']} computed now, {s['reused']} found in the folder; {s['elapsed_s']:.1f} s "
             f"({s['executor']})"]
    rows = [r for r in result.rows if r["peak_amplitude_m"] is not None]
    if rows:
        for word, pick in (("smallest", min), ("largest", max)):
            r = pick(rows, key=lambda x: x["peak_amplitude_m"])
            where = ", ".join(f"{p} = {r[p]}" for p in result.parameters)
            lines.append(f"{word} peak: {r['peak_amplitude_m']:.6g} m at omega = {r['peak_omega_rad_s']:.6g} rad/s "
                         f"(run {r['run']}: {where})")
    lines += [f"wrote {Path(p).resolve()}" for p in result.files.values()]
    if not result.success:
        lines.append(f"failed: {result.message}")
    return lines


def _default_arguments(parser):
    _common(parser, suppress=True)
    _model_argument(parser)


def _tol(args: argparse.Namespace) -> float:
    """``--tol`` of the main job (``frequency_response``'s default, ``hbm.frf.DEFAULT_TOL``, where not given)."""
    tol = getattr(args, "tol", None)
    return DEFAULT_TOL if tol is None else tol


def _seconds(text: str) -> float:
    """argparse's type of ``--time-limit``: a number of seconds > 0."""
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0.0 < value < math.inf:
        raise argparse.ArgumentTypeError(f"must be a number of seconds > 0, got --time-limit {text}")
    return value


def _workers(text: str) -> int:
    """argparse's type of ``--workers``: an integer >= 1 (as ``study.workers``; ``run_study`` refused 0 only once
    the study started, as a failed computation, and ``--check`` passed it)."""
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be an integer >= 1 (processes), got --workers {text}")
    return value


def _relative(option: str, upper: float, names: dict | None = None) -> Callable[[str], float]:
    """argparse's type of a relative tolerance ``option``: a number in [MIN_RELATIVE_TOL, upper), or a name of
    ``names`` standing for its number (``--tol precise``, as ``frequency_response(tol="precise")``)."""
    named = "" if not names else " or one of " + ", ".join(f"{n} ({v:g})" for n, v in names.items())

    def parse(text: str) -> float:
        if names and text in names:
            return float(names[text])
        try:
            value = float(text)
        except ValueError:
            value = math.nan
        if not MIN_RELATIVE_TOL <= value < upper:
            raise argparse.ArgumentTypeError(
                f"must be a number in [{MIN_RELATIVE_TOL:g}, {upper:g}) (a relative error; below {MIN_RELATIVE_TOL:g} "
                f"double precision cannot meet it){named}, got {option} {text}")
        return value

    return parse


def _model_argument(parser, suppress=True):
    """``--model`` and ``--tol``: the main job's damper model and target relative error."""
    parser.add_argument("--tol", type=_relative("--tol", 1.0, PRESETS), default=argparse.SUPPRESS if suppress else None,
                        help=f"the main job's target relative error of every point (default {DEFAULT_TOL:g}): a "
                             "number, or fast, default, precise as frequency_response's tol")
    parser.add_argument("--model", choices=MODELS, default=argparse.SUPPRESS if suppress else None,
                        help="where the main job uses the damper's refined model, the bar with every mode "
                             "(frequency_response's model=): 'auto' (default: in every window of the curve where "
                             "the single-mode bar is further than its share of tol from it, the physical curve; "
                             "about 9 s), 'peak' (in those of the windows that hold the peak, the single-mode bar "
                             "elsewhere; for the default case as long as 'auto': the windows that hold its peak span "
                             "its slip range) or 'given' (the single-mode bar only; about 1 s). Times: CPU seconds "
                             "of the whole job, benchmarks/bench_stated_times.py")


def _run_arguments(parser):
    _common(parser, suppress=True, scene=True)
    parser.add_argument("scene", help="the scene file (TOML, docs/scenes.md)")
    parser.add_argument("--tol", nargs="?", action=_SceneTol, dest="scene_tol", default=argparse.SUPPRESS,
                        help=argparse.SUPPRESS)  # refused, naming --set sweep.tol
    parser.add_argument("--set", action="append", default=[], metavar="TABLE.KEY=VALUE",
                        help="override a key of the scene (VALUE in TOML syntax), e.g. --set sweep.max_step=0.1")
    parser.add_argument("--quiet", action="store_true", help="no progress line")
    parser.add_argument("--check", action="store_true", help="validate and print the effects; compute nothing")
    parser.add_argument("--workers", type=_workers, default=None, metavar="N",
                        help="a study: processes (or Dask LocalCluster workers); default every core")
    parser.add_argument("--scheduler", default=None, metavar="ADDRESS",
                        help="a study: run on the Dask scheduler at ADDRESS (tcp://host:8786)")
    parser.add_argument("--executor", default=None, choices=("processes", "serial", "dask"),
                        help="a study: where the runs go (default study.executor, else processes)")
    parser.add_argument("--time-limit", type=_seconds, default=None, metavar="S",
                        help="a study: seconds each run may take; a run over it fails naming the limit (default "
                             "study.time_limit, else none)")


def _new(args) -> int:
    path = Path(args.scene)
    if path.is_dir():
        raise UsageError(f"{path} is a folder; new writes a scene file: give its name (new {path / 'scene.toml'})")
    if path.exists() and not args.force:
        print(f"error: {path} exists (pass --force to overwrite it)", file=sys.stderr)
        return 2
    if not path.parent.is_dir():
        raise UsageError(f"the folder {path.parent} of {path} does not exist; create it first (mkdir -p {path.parent})")
    from ..scenes.template import template  # lazily: as in _run

    try:
        path.write_text(template(path.stem))
    except OSError as exc:
        raise UsageError(f"cannot write {path}: {exc.strerror or exc}") from None
    print(f"wrote {path.resolve()}: run it with: {args.prog} run {path}")
    return 0


def _new_arguments(parser):
    parser.add_argument("scene", help="the scene file to write (TOML)")
    parser.add_argument("--force", action="store_true", help="overwrite an existing file")


def _models(args) -> int:
    from ..scenes import MODELS  # lazily: as in _run

    width = max(len(name) for name in MODELS)
    for name, spec in MODELS.items():
        own = f" (keys: {', '.join('damper.' + k for k in spec.keys)})" if spec.keys else ""
        print(f"{name.ljust(width)}  {spec.doc}{own}")
    return 0


def _keys(args) -> int:
    from ..scenes import REQUIRED, schema  # lazily: as in _run
    from ..scenes.checks import dot, show  # lazily: as in _run

    for table, keys in schema().items():
        print(f"[{table}]" if table else "(top level)")
        for key, spec in keys.items():
            default = ("required" if spec.default is REQUIRED else "optional" if spec.default is None
                       else f"default {show(list(spec.default) if isinstance(spec.default, tuple) else spec.default)}")
            print(f"  {dot(table, key)}: {default}; {spec.doc}")
    return 0


#: Subcommands: name -> (help, handler[, add_arguments]).  Each subcommand takes only the options
#: its ``add_arguments`` declares (``--out`` and ``--rtol`` only ``default`` and ``run``).  No
#: subcommand runs ``default``.
COMMANDS = {"default": ("run the main job, the built-in default case (the same as no subcommand): default [--out DIR] [--rtol X] "
                        "[--model M] [--tol X]",
                        _default, _default_arguments),
            "run": ("run a scene file: run SCENE.toml [--out DIR] [--set TABLE.KEY=VALUE] [--rtol X] [--quiet] "
                    "[--check] [--workers N] [--scheduler ADDRESS] [--executor NAME] [--time-limit S] (the last "
                    "four for a scene with [study])", _run, _run_arguments),
            "new": ("write an annotated template scene that runs as written: new SCENE.toml [--force]", _new,
                    _new_arguments),
            "models": ("list the damper models a scene can name", _models),
            "keys": ("list every key of a scene with its default and meaning", _keys)}


#: Where a scene's target error is set: ``run`` has no ``--tol`` (the main job's), and says this instead.
SCENE_TOL = "a scene's target error is its sweep.tol: give --set sweep.tol={value}"


def _common(parser, suppress=False, scene=False):
    """``--out`` and ``--rtol``: options of the main job, given before any subcommand or after
    ``default`` or ``run`` (after it they override); the other subcommands refuse them.  ``scene``: run's
    (its --rtol says what sets a scene's accuracy instead)."""
    default = (lambda v: argparse.SUPPRESS) if suppress else (lambda v: v)
    parser.add_argument("--out", default=default(None),
                        help="output folder (default: the current folder; for run, the scene's output.folder)")
    instead = ("it overrides sweep.tolerance; use --set sweep.tol=VALUE instead, the target relative error, which "
               "sets it" if scene else "use --tol instead (for run, --set sweep.tol=VALUE), the target relative "
               "error, which sets it")
    parser.add_argument("--rtol", type=_relative("--rtol", MAX_RTOL), default=default(None),
                        help=f"deprecated: the elements' relative accuracy; {instead} (tol/100, at most 1e-6)")


class _SceneTol(argparse.Action):
    """``run ... --tol X``: refused in one line pointing to ``--set sweep.tol=X`` (argparse would report
    "unrecognized arguments" and nothing more)."""

    def __call__(self, parser, namespace, values, option_string=None):
        value = values if isinstance(values, str) and values else "VALUE"
        parser.error(f"--tol does not apply to run: {SCENE_TOL.format(value=value)}")


def program_name(argv0: str | None = None) -> str:
    """How the user called us: ``python3 -m hbm`` or the console script's name."""
    argv0 = sys.argv[0] if argv0 is None else argv0
    name = os.path.basename(argv0)
    return "python3 -m hbm" if name in ("__main__.py", "-m", "") else name


def build_parser(prog: str | None = None) -> argparse.ArgumentParser:
    """The command line's parser; ``prog`` defaults to :func:`program_name`."""
    prog = program_name() if prog is None else prog
    parser = argparse.ArgumentParser(prog=prog, description=DESCRIPTION, epilog=EXAMPLES.format(prog=prog),
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--version", action="version", version=f"%(prog)s {__version__}")
    _common(parser)
    _model_argument(parser, suppress=False)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name, (text, handler, *arguments) in COMMANDS.items():
        p = sub.add_parser(name, help=text, description=text)
        for add in arguments:
            add(p)
        p.set_defaults(handler=handler, takes=frozenset(a.dest for a in p._actions))
    parser.set_defaults(handler=_default, prog=prog, takes=frozenset({"out", "rtol", "model", "tol"}))
    return parser


def _parse(parser: argparse.ArgumentParser, argv: list[str] | None) -> argparse.Namespace:
    """Parse ``argv``; ``--out``/``--rtol`` given before a subcommand that does not take them is an
    error (exit code 2), not an option silently ignored; an option that no command takes is named as such
    (argparse would otherwise report the value after it as an unknown command)."""
    known = {o for p in _parsers(parser) for a in p._actions for o in a.option_strings}
    for token in (sys.argv[1:] if argv is None else argv):
        if token == "--":
            break
        name = token.split("=", 1)[0]
        if name.startswith("--") and len(name) > 2 and not any(o.startswith(name) for o in known):
            parser.error(f"unrecognized option: {name}")
    args = parser.parse_args(argv)
    for dest in ("out", "rtol", "model", "tol"):
        if getattr(args, dest) is not None and dest not in args.takes:
            where = "the main job" if dest in ("model", "tol") else "the main job and run"
            scene = f"; {SCENE_TOL.format(value='VALUE')}" if (dest, args.command) == ("tol", "run") else ""
            parser.error(f"--{dest} does not apply to {args.command} (only to {where}){scene}")
    return args


def _parsers(parser: argparse.ArgumentParser) -> list[argparse.ArgumentParser]:
    """``parser`` and its subcommands' parsers."""
    subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return [parser] + [p for a in subs for p in a.choices.values()]


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``python3 -m hbm`` and the ``frictiondamp`` console script."""
    args = _parse(build_parser(), argv)
    previous = signal.signal(signal.SIGTERM, _terminate)
    shown = warnings.formatwarning
    warnings.formatwarning = _one_line  # every warning shown as one line (a recording caller still records it)
    try:
        code = args.handler(args)
        sys.stdout.flush()  # a full device or a closed pipe shows here, not at the interpreter's exit
        return code
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt as exc:  # between the jobs' own handling (a listing, a template)
        print(_stopped(exc), file=sys.stderr)
        return _interrupted_code(exc)
    except BrokenPipeError:  # the reader went away (keys | head -1): stop quietly, as SIGPIPE would
        _stdout_to_devnull()
        return 141
    except (ComputationFailed, ValueError) as exc:  # not found in the input: a failure of the computation
        print(f"error: the computation failed: {exc}", file=sys.stderr)
        return 1
    except OSError as exc:  # stdout on a full device, a file that cannot be written
        _stdout_to_devnull()
        print(f"error: cannot write: {exc}", file=sys.stderr)
        return 1
    finally:
        signal.signal(signal.SIGTERM, previous)
        warnings.formatwarning = shown


def _stdout_to_devnull() -> None:
    """Point stdout at the null device, so that the interpreter's last flush raises nothing."""
    try:
        fd = os.open(os.devnull, os.O_WRONLY)
        os.dup2(fd, sys.stdout.fileno())
        os.close(fd)
    except (OSError, ValueError):
        pass
