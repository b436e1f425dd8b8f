"""Command-line interface: argparse over :mod:`spectralshell.api`; parses, prints, writes files.

Every error the user can cause prints one line to stderr and exits with status 2; a computation
that cannot reach its accuracy exits with status 1. So do, with one line each, a run out of
memory, a file system that fails during the run, and an arithmetic overflow that validation
should have prevented (then a bug to report: the line names the exception); any other
exception is a bug and keeps its traceback.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import re
import shlex
import sys
import tempfile
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, NoReturn

from ._validate import (parse_int, parse_real, require_int_in_range, require_output_file,
                        require_writable_directory)
from ._version import __version__
from .errors import ConvergenceError, ParameterError, SpectralShellError, SweepInterrupted
from .params.registry import (get_model, load_entry_points, models, models_with, param_fields,
                              param_help, param_names, stepping_keywords)
from .params.scene import default_scene, is_simulation_scene, load_scene, plan
from .params.sweep_grid import is_sweep_scene, sweep_spec


def _api():
    """:mod:`spectralshell.api`, imported when a command computes (it brings scipy and the
    solvers; ``--version`` and ``--help`` do without)."""
    from . import api

    return api


class _Parser(argparse.ArgumentParser):
    """The CLI's parsers: errors in one line (status 2); every command and sub-command takes
    the global flag --quiet (anywhere on the line)."""

    def __init__(self, *args: Any, **kwargs: Any):
        super().__init__(*args, **kwargs)
        self.add_argument("-q", "--quiet", action="store_true", default=argparse.SUPPRESS,
                          help="no progress on stderr (by default long work shows a bar with "
                               "ETA on a terminal, a line every few seconds when piped)")

    def error(self, message: str) -> NoReturn:  # one line, status 2
        raise ParameterError(message)



def _flag(name: str) -> str:
    return f"--{name.replace('_', '-')}"


def _model_flags(p: argparse.ArgumentParser, model: str, *, skip: Sequence[str] = ()) -> None:
    """One flag per parameter of ``model`` (its meaning, units and default from the parameter
    metadata of the registry)."""
    group = p.add_argument_group(f"parameters of model {model!r}")
    for f in param_fields(model):
        if f.name in skip:
            continue
        default = "" if f.default in (dataclasses.MISSING, None) else f" (default {f.default})"
        group.add_argument(_flag(f.name), dest=f.name, metavar="X", help=param_help(f) + default)


def _physical_flags(p: argparse.ArgumentParser, units: dict[str, str], note: str) -> None:
    """Flags of a model's cgs inputs (quantity -> unit)."""
    group = p.add_argument_group("physical input (cgs)", note or None)
    for name, unit in units.items():
        group.add_argument(_flag(name), dest=name, metavar="X", help=f"{name} ({unit})")


def _solver_flags(p: argparse.ArgumentParser) -> None:
    g = p.add_mutually_exclusive_group()
    g.add_argument("--tol", type=str, default="1e-10", help="absolute tolerance on tau_min (default 1e-10)")
    g.add_argument("--n-temporal", dest="n_temporal", metavar="N",
                   help="fix the temporal truncation N instead of converging to --tol")


def _tau_max_flag(p: argparse.ArgumentParser) -> None:
    p.add_argument("--tau-max", dest="tau_max", metavar="X",
                   help="compute only the marginal tau <= X, e.g. 0.5 (positive stiffness; "
                        "default: all)")


def _given(args: argparse.Namespace, name: str, convert: Callable[[str, str], Any]) -> dict:
    """{name: the flag's value converted} if the flag was given, else {}."""
    value = getattr(args, name)
    return {} if value is None else {name: convert(name, value)}


def _tau_max(args: argparse.Namespace) -> dict[str, float]:
    return _given(args, "tau_max", parse_real)


def _max_seconds_flag(p: argparse.ArgumentParser) -> None:
    p.add_argument("--max-seconds", dest="max_seconds", metavar="X",
                   help="raise the limit on the estimated cost of the solve (default "
                        "600 s, or $SPECTRALSHELL_MAX_SECONDS)")


def _max_points_flag(p: argparse.ArgumentParser) -> None:
    p.add_argument("--max-points", dest="max_points", metavar="N",
                   help="raise the limit on grid points (default 1000000, or "
                        "$SPECTRALSHELL_MAX_POINTS)")


def _params(args: argparse.Namespace, model: str, *, skip: Sequence[str] = (),
            grids: bool = False) -> dict[str, Any]:
    """The model parameters given as flags, each as its parameter's type; with ``grids``, a real
    parameter given as a range START:STOP:NUM is kept as that text (the API parses it)."""
    def value(f) -> Any:
        text = getattr(args, f.name)
        if grids and f.type in (float, "float") and ":" in text:
            return text
        return _typed(f.name, text, f.type)

    return {f.name: value(f) for f in param_fields(model)
            if f.name not in skip and getattr(args, f.name, None) is not None}


def _typed(name: str, text: str, kind: object) -> Any:
    """A flag's text as its parameter's type: str kept, an integer literal for an int field
    (so that the validator's message repeats what was typed), a number or else the text for
    (float, str) (an expression), otherwise a float."""
    if kind in (str, "str"):
        return text
    if kind == (float, str):
        return text if _is_text(text) else parse_real(name, text)
    if kind in (int, "int"):
        try:
            return parse_int(name, text)
        except ParameterError:
            return text  # the parameter's own validator says what is allowed
    return parse_real(name, text)


def _solver(args: argparse.Namespace) -> dict[str, Any]:
    out: dict[str, Any] = {"tol": parse_real("tol", args.tol)}
    if args.n_temporal is not None:
        try:
            out["n_temporal"] = int(args.n_temporal)
        except ValueError:
            raise ParameterError(f"n_temporal = {args.n_temporal!r} is invalid: must be an integer "
                                 "in [1, 400]") from None
    return out


#: Figure files the CLI writes, the format chosen by the suffix.
FIGURE_SUFFIXES = (".png", ".svg", ".pdf")
#: The --png flags' help: what a figure file may be.
FIGURE_FILE = "a *.png, *.svg or *.pdf file (format from the suffix; an existing file is replaced)"


def _check_output(name: str, path: str | Path | None, suffix: str | tuple[str, ...]) -> None:
    """Refuse output file ``name`` = ``path`` unless it can be written: a new or existing
    (replaced) regular file ending in ``suffix`` (or one of them) in a writable directory
    (:func:`spectralshell._validate.require_output_file`)."""
    if path is not None:
        require_output_file(name, path, (suffix,) if isinstance(suffix, str) else suffix)


def _make_dir(out: str | Path) -> Path:
    """Create the output directory ``out`` (with parents), or say in one line why it cannot be."""
    out = Path(out)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ParameterError(f"output directory {str(out)!r} cannot be created: "
                             f"{exc.strerror or exc}") from None
    require_writable_directory("output directory", out, out)
    return out


def _atomic_write(path: str | Path, writer: Callable[[Path], Any]) -> None:
    """Write via a temporary file in the same directory, so no partial file is ever left; the
    file gets the permissions of a plainly created one (mkstemp's are owner-only)."""
    path = Path(path)
    suffix = "".join(path.suffixes) or ".tmp"
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=".partial-", suffix=suffix)
    os.close(fd)
    try:
        writer(Path(tmp))
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)


def _emit_json(obj: dict) -> None:
    sys.stdout.write(json.dumps(obj, allow_nan=False) + "\n")


def _report(as_json: bool, data: dict, text: Callable[[], str], written: Sequence[str] = ()) -> int:
    """Print exactly one JSON object, or the human summary and the files written; exit status 0."""
    if as_json:
        _emit_json(data)
    else:
        print(text())
        for path in written:
            print(f"wrote {path}")
    return 0


def _unproved(count: int, note: str) -> int:
    """Exit status of a finished map, sweep or diagram: 0, or with ``count`` uncertified points
    (no tau found, none proved: issue 23) 1 after one line ``note`` on stderr."""
    if not count:
        return 0
    print(f"spectralshell: not proved: {note}", file=sys.stderr)
    return 1


def _progress(args: argparse.Namespace) -> bool:
    """Whether long work reports its progress on stderr (a bar on a terminal, a line every
    few seconds when piped): not with --quiet, nor with --json (a program reads the output)."""
    return not (getattr(args, "quiet", False) or getattr(args, "json", False))


def _warn(warnings: Sequence[str]) -> None:
    for w in warnings:
        print(f"warning: {w}", file=sys.stderr)


def _physical(args: argparse.Namespace, units: dict[str, str] | None = None) -> dict[str, float]:
    """The cgs inputs given as flags (``units``: the model's Floquet physical input by default)."""
    if units is None:
        spec = get_model(args.model).physical
        units = {} if spec is None else dict(spec.units)
    return {k: parse_real(k, getattr(args, k)) for k in units if getattr(args, k, None) is not None}


def _nonuniform(args: argparse.Namespace) -> dict[str, Any]:
    """The sphere's kappa given as an expression in theta, phi (kept as text) and --l-max
    ('auto' or an integer); {} otherwise (a number keeps the per-degree path)."""
    if args.model != "sphere":
        return {}
    out: dict[str, Any] = {}
    if args.kappa is not None and _is_text(args.kappa):
        out["kappa"] = args.kappa
    if args.l_max is not None:
        out["l_max"] = args.l_max if args.l_max == "auto" else _integer("l_max", args.l_max)
    return out


def cmd_floquet(args) -> int:
    extra = _physical(args)
    for name in ("tol_spatial", "max_seconds"):
        if getattr(args, name, None) is not None:
            extra.update(_given(args, name, parse_real))
    text = _nonuniform(args)
    res = _api().floquet(args.model, kind=args.kind, **_solver(args), **extra, **_tau_max(args),
                         progress=_progress(args), **_params(args, args.model, skip=tuple(text)),
                         **text)
    _warn(res.warnings)
    return _report(args.json, res.to_dict(), res.summary)


def _write_tongues(res, *, png=None, csv=None, npz=None) -> list[str]:
    written = []
    if png:
        from .plots import ince_strutt
        _atomic_write(png, lambda p: ince_strutt.save([res], p))
        written.append(png)
    if csv:
        _atomic_write(csv, res.write_csv)
        written.append(csv)
    if npz:
        _atomic_write(npz, lambda p: res.write_npz(open(p, "wb")))
        written.append(npz)
    return written


def cmd_tongues(args) -> int:
    for flag, suffix in (("png", FIGURE_SUFFIXES), ("csv", ".csv"), ("npz", ".npz")):
        _check_output(f"--{flag}", getattr(args, flag), suffix)
    if args.kappa is None:
        raise ParameterError("--kappa is required: a range START:STOP:NUM, e.g. 0:3:301")
    res = _api().tongues(args.model, kappa=args.kappa, kind=args.kind, tips=not args.no_tips,
                      boundaries=not args.no_boundaries,
                      workers=args.workers, progress=_progress(args),
                      **_solver(args), **_tau_max(args), **_given(args, "max_points", _integer),
                      **_params(args, args.model, skip=("kappa",)))
    note = res.uncertified_note()  # the exit line below, not a warning too
    _warn([w for w in res.warnings if w != note])
    written = _write_tongues(res, png=args.png, csv=args.csv, npz=args.npz)
    _report(args.json, res.to_dict(), res.summary, written)
    return _unproved(len(res.uncertified), note)


def cmd_exponents(args) -> int:
    if args.tau is None:
        raise ParameterError("--tau is required: the forcing amplitude")
    count = None if args.count is None else require_int_in_range("count", parse_int("count", args.count), 1)
    text = _nonuniform(args)
    priced = _given(args, "max_seconds", parse_real) if hasattr(args, "max_seconds") else {}
    res = _api().exponents(args.model, tau=parse_real("tau", args.tau), count=count,
                           **_solver(args), **priced,
                           **_params(args, args.model, skip=tuple(text)), **text)
    _warn(res.warnings)
    return _report(args.json, res.to_dict(), res.summary)


def cmd_stability(args) -> int:
    if args.tau is None or args.m is None:
        raise ParameterError("--tau and --m are required, e.g. --tau 0.45 --m 2:6")
    res = _api().stability(args.model, tau=parse_real("tau", args.tau), m=args.m, kind=args.kind,
                        **_solver(args), **_params(args, args.model, skip=("m",), grids=True))
    note = res.unproved_note()  # the exit line below, not a warning too
    _warn([w for w in res.warnings if w != note])
    _report(args.json, res.to_dict(), res.summary)
    return _unproved(res.unproved(), note)


def cmd_modes(args) -> int:
    physical = _physical(args, dict(get_model(args.model).mode_inputs))
    count = None
    if args.count is not None:
        try:
            count = int(args.count)
        except ValueError:
            raise ParameterError(f"count = {args.count!r} is invalid: must be an integer >= 1") from None
    precision = None
    if args.precision is not None:
        try:
            precision = int(args.precision)
        except ValueError:
            raise ParameterError(f"precision = {args.precision!r} is invalid: must be an integer "
                                 "number of digits") from None
    res = _api().natural_modes(args.model, count=count, precision=precision,
                            zeta=None if args.zeta is None else parse_real("zeta", args.zeta),
                            physical=physical or None, **_params(args, args.model))
    _warn(res.warnings)
    return _report(args.json, res.to_dict(), res.summary)


def cmd_response(args) -> int:
    _check_output("--png", args.png, FIGURE_SUFFIXES)
    res = _api().response(args.model, kind=args.kind, **_solver(args), **_physical(args),
                       **_given(args, "max_seconds", parse_real), **_params(args, args.model))
    _warn(res.warnings)
    written = []
    if args.png:
        from .plots import cochlea as cochlea_plots

        title = cochlea_plots.response_title(res)
        _atomic_write(args.png, lambda path: cochlea_plots.save_responses([(title, [res])], path))
        written.append(args.png)
    return _report(args.json, res.to_dict(), res.summary, written)


def _integer(name: str, text: str) -> int:
    """A count given on the command line (--workers, --max-points, --m, ...): read as every
    integer flag is (:func:`~spectralshell._validate.parse_int`: '3', '3.0', '1e3'), then
    checked to be a whole number >= 0; ranges are the callee's."""
    return require_int_in_range(name, parse_int(name, text), 0)


def cmd_lp(args) -> int:
    if args.m is None:
        raise ParameterError("--m is required, e.g. --m 2")
    data = _api().lp_summary(_integer("m", args.m), _integer("k", args.k), volume=args.volume,
                          check=args.check)

    def text() -> str:
        lines = [f"sphere, inviscid, radial-only displacement, shape 1 + eps Y_{{{data['m']},{data['k']}}}:",
                 f"  lambda = lambda0 (1 + c eps^2),  c = {data['coefficient_exact']} = "
                 f"{data['coefficient']:.15g}",
                 f"  lambda0 / sqrt(kappa) = {data['lambda0_over_sqrt_kappa']:.15g}"]
        if "check" in data:
            lines.append(f"  direct nonlinear solve: slope = {data['check']['slope']:.12g} "
                         f"+- {data['check']['uncertainty']:.1e}  "
                         f"(difference {abs(data['check']['slope'] - data['coefficient']):.1e})")
        return "\n".join(lines)

    return _report(args.json, data, text)


def cmd_figure(args) -> int:
    from .reports.figures import FIGURES, make_figure

    if args.name == "list":
        width = max(map(len, FIGURES))
        print("\n".join(f"{name:<{width}}  {text}" for name, (text, _) in FIGURES.items()))
        return 0
    if args.name not in FIGURES:
        raise ParameterError(f"figure = {args.name!r} is invalid: must be one of {', '.join(FIGURES)} "
                             "(or 'list')")
    out = Path(args.out)
    _make_dir(out)
    if _progress(args):
        print(f"{args.name}: computing {FIGURES[args.name][0]}", file=sys.stderr)
    for path in make_figure(args.name, out, progress=_progress(args), workers=args.workers):
        print(f"wrote {path}")
    return 0


def cmd_validate(args) -> int:
    """Run the validation cases, write report.md, report.html (self-contained), report.json and
    PNGs; status 1 if any case fails."""
    from .reports import validation

    workers = None if args.workers is None else _integer("workers", args.workers)
    if workers is not None and workers < 1:
        raise ParameterError(f"workers = {workers} is invalid: must be an integer >= 1")
    out = _make_dir(args.out)

    def show(outcome) -> None:  # every case as it ends; with --quiet, the failures only
        if outcome.passed and not _progress(args):
            return
        print(f"{'pass' if outcome.passed else 'FAIL'}  {outcome.case.name}  ({outcome.seconds:.1f} s)"
              + (f"  {outcome.message}" if outcome.message else ""), file=sys.stderr)

    report = validation.run(out, quick=args.quick, workers=workers, progress=show)
    n, failed = len(report.outcomes), len(report.failures)
    print(f"validation ({'quick' if args.quick else 'full'}): {n - failed} of {n} cases pass "
          f"in {report.seconds:.1f} s -> {out / 'report.md'}, {out / 'report.html'}")
    return 0 if report.passed else 1


def _summary(results: dict[str, Any]) -> str:
    """A scene's text: the Floquet summary, the exponents' headline, the diagram's summary."""
    parts = []
    if "floquet" in results:
        parts.append(results["floquet"].summary())
    if "exponents" in results:
        parts.append(results["exponents"].headline())
    if "tongues" in results:
        parts.append(results["tongues"].summary())
    return "\n".join(parts)


def _run(scene, out_dir: str | None, as_json: bool, name: str, progress: bool) -> int:
    the_plan = plan(scene)
    out = Path(out_dir or the_plan.output_dir)
    _make_dir(out)
    png, json_path = out / "ince_strutt.png", out / f"{name}.json"
    _check_output("output", png, ".png")
    _check_output("output", json_path, ".json")
    results = _api().run_scene(the_plan, progress=progress)
    for r in results.values():  # a diagram's uncertified note is the exit line (_unproved)
        _warn([w for w in r.warnings if w != getattr(r, "uncertified_note", str)()])
    data = {k: r.to_dict() for k, r in results.items()}
    written = []
    if "tongues" in results:
        written += _write_tongues(results["tongues"], png=str(png))
    _atomic_write(json_path, lambda p: p.write_text(json.dumps(data, indent=1)))
    written.append(str(json_path))
    _report(as_json, data, lambda: _summary(results), written)
    diagram = results.get("tongues")
    return 0 if diagram is None else _unproved(len(diagram.uncertified),
                                               diagram.uncertified_note())


def cmd_demo(args) -> int:
    return _run(default_scene(), args.out, args.json, "demo", _progress(args))


def _run_sweep(scene: dict, out_dir: str | None, as_json: bool, name: str,
               progress: bool, max_seconds: dict | None = None) -> int:
    """A scene with a [grid]: the sweep runner writes NAME.zarr (resumable) and NAME.png."""
    output = scene.get("output", {})
    out = Path(out_dir or (output.get("dir") if isinstance(output, dict) else None)
               or "scene-output")
    sweep_spec({k: v for k, v in scene.items() if k != "output"})  # validate before creating out
    _make_dir(out)
    store, png = out / f"{name}.zarr", out / f"{name}.png"
    _check_output("output", png, ".png")
    summary = _api().sweep_summary({k: v for k, v in scene.items() if k != "output"},
                                out=str(store), progress=progress, **(max_seconds or {}))
    from .plots import sweep_plot

    _atomic_write(png, lambda p: sweep_plot.save(_api().open_sweep(store), p))
    _report(as_json, {**summary, "png": str(png)}, lambda: _sweep_text(summary), [str(png)])
    return _sweep_status(summary, sweep_spec({k: v for k, v in scene.items() if k != "output"}))


def cmd_run(args) -> int:
    scene = load_scene(args.scene)
    if is_sweep_scene(scene):
        return _run_sweep(scene, args.out, args.json, Path(args.scene).stem, _progress(args),
                          _given(args, "max_seconds", parse_real))
    if args.max_seconds is not None:
        raise ParameterError(f"--max-seconds {args.max_seconds} is invalid here: it limits the "
                             "estimated cost of a sweep scene (one with a [grid]; a fibre or "
                             "cochlea simulation scene takes max_seconds in its [simulate])")
    if is_simulation_scene(scene):
        return _simulate_scene(scene, Path(args.scene).stem, args.out, None, None, args.json,
                               _progress(args))
    return _run(scene, args.out, args.json, Path(args.scene).stem, _progress(args))


def _sweep_text(summary: dict) -> str:
    where = f" -> {summary['out']}" if summary["out"] else ""
    repaired = (f", {summary['damaged']} of them replacing damaged chunks of the store"
                if summary["damaged"] else "")
    if summary["outdated"]:
        repaired += (f", {summary['outdated']} of them in outdated chunks of the store (written "
                     "by an earlier spectralshell whose values are not kept), recomputed")
    if summary["uncertified"]:
        repaired += f"; {summary['uncertified']} uncertified (no tau found, none proved)"
    return (f"sweep: {summary['points']} points ({summary['computed']} computed{repaired}, "
            f"{summary['skipped']} already in the store) in {summary['seconds']:.1f} s{where}")


def _sweep_status(summary: dict, spec) -> int:
    """:func:`_unproved` of a finished sweep (its summary and SweepSpec)."""
    from .results.maps import uncertified_note

    return _unproved(summary["uncertified"], uncertified_note(
        summary["uncertified"], summary["points"], spec.options.tau_max))


def cmd_sweep(args) -> int:
    executor = args.executor or ("dask" if args.scheduler else "processes")
    scene = sweep_spec(args.scene, **_given(args, "max_points", _integer))
    summary = _api().sweep_summary(scene, executor=executor, workers=args.workers,
                                scheduler=args.scheduler, out=args.out,
                                progress=_progress(args),
                                **_given(args, "max_seconds", parse_real))
    _report(args.json, summary, lambda: _sweep_text(summary))
    return _sweep_status(summary, scene)


def cmd_plot(args) -> int:
    _check_output("--png", args.png, FIGURE_SUFFIXES)
    from .plots import sweep_plot

    from .results.maps import uncertified, uncertified_note

    ds = _api().open_sweep(args.store)
    _atomic_write(args.png, lambda p: sweep_plot.save(ds, p))
    print(f"wrote {args.png}")
    count = int(uncertified(ds).sum())
    if count:  # drawn hatched and named in the legend: the picture is honest
        _warn([uncertified_note(count, int(ds["tau_min"].size),
                                float(ds.attrs.get("tau_max", 0.5)))])
    return 0


def _simulation_keywords(args) -> dict[str, Any]:
    """The keywords of ``spectralshell simulate MODEL --flag ...`` (a model that can be
    time-stepped), each flag's text as the keyword's type; a flag the model does not take is
    refused."""
    known = stepping_keywords(args.target)
    given = {name: getattr(args, name) for name in _simulation_flags()
             if getattr(args, name, None) is not None}
    for name in given:
        if name not in known:
            raise ParameterError(f"{_flag(name)} is invalid for model {args.target!r}: "
                                 f"expected {', '.join(_flag(k) for k in known)}")
    return {name: _typed(name, text, known[name][0]) for name, text in given.items()}


def _simulation_flags() -> dict[str, str]:
    """Every flag of ``simulate`` (a keyword of some model that can be time-stepped) -> its
    help: the one help, with the models that take it when not all do, or each model's where
    they differ."""
    helps: dict[str, dict[str, str]] = {}
    names = models_with("time_stepping")
    for model in names:
        for name, (_, text) in stepping_keywords(model).items():
            helps.setdefault(name, {})[model] = text
    out = {}
    for name, by_model in helps.items():
        texts = set(by_model.values())
        if len(texts) > 1:
            out[name] = "; ".join(f"{model}: {text}" for model, text in by_model.items())
        else:
            out[name] = texts.pop() + ("" if len(by_model) == len(names)
                                       else f" [{', '.join(by_model)}]")
    return out


def _is_text(value: str) -> bool:
    try:
        float(value)
        return False
    except ValueError:
        return True


def _figure_paths(png: str | None, figures: tuple[str, ...]) -> list[str]:
    """The files ``simulate --png PNG`` writes for a model whose registration names
    ``figures`` (suffixes of PNG's stem, '' for PNG itself): the sphere's membrane shape goes
    to NAME_shape with the same suffix."""
    if not png:
        return []
    path = Path(png)
    return [str(path.with_name(f"{path.stem}{extra}{path.suffix}")) for extra in figures]


def _write_simulation(run, pngs: list[str], npz: str | None) -> list[str]:
    """Write the run's figures (``pngs`` of :func:`_figure_paths`) and its NPZ."""
    from .results.stepped import SteppedRun

    written = []
    if pngs and isinstance(run, SteppedRun):
        from .plots import stepped as plot

        from .runner.simulate import leading_exponent

        try:
            exponent: complex | None = leading_exponent(run)
        except SpectralShellError as exc:
            exponent = None
            _warn([f"the figure has no Floquet exponent drawn: {' '.join(str(exc).split())}"])
        _atomic_write(pngs[0], lambda p: plot.save(run, p, exponent=exponent))
        written += pngs
    elif pngs:
        from .plots import trajectory as plot

        from .runner.simulate import shape_snapshots

        png, shape_png = pngs
        _atomic_write(png, lambda p: plot.save_amplitudes(run, p))
        theta, phi, fields, times = shape_snapshots(run)
        _atomic_write(shape_png, lambda p: plot.save_shape(theta, phi, fields, times, p))
        written += pngs
    if npz:
        _atomic_write(npz, run.write_npz)
        written.append(npz)
    return written


def cmd_simulate(args) -> int:
    if args.target not in models():
        given = [_flag(f) for f in _simulation_flags() if getattr(args, f) is not None]
        if given:
            raise ParameterError(f"{given[0]} is invalid with a scene file: set it in the scene")
        return _simulate_scene(load_scene(args.target), Path(args.target).stem, None, args.png,
                               args.npz, args.json, _progress(args))
    return _simulation(args.target, args.target, _simulation_keywords(args), args.png, args.npz,
                       None, args.json, _progress(args))


def _simulate_scene(data: dict, stem: str, out_dir: str | None, png: str | None,
                    npz: str | None, as_json: bool, progress: bool) -> int:
    """A simulation scene (``simulate FILE``, ``run FILE``): NAME.json, NAME.npz and the
    figures (NAME.png) written to ``out_dir`` or the scene's directory unless given."""
    from .params.simulation import simulation_scene

    scene = simulation_scene(data)
    out = _make_dir(out_dir or scene.output_dir)
    if get_model(scene.model).time_stepping.figures:
        png = png or str(out / f"{stem}.png")
    return _simulation(scene.model, data, {}, png, npz or str(out / f"{stem}.npz"),
                       out / f"{stem}.json", as_json, progress)


def _simulation(model: str, target: str | dict, keywords: dict[str, Any], png: str | None,
                npz: str | None, json_path: Path | None, as_json: bool, progress: bool) -> int:
    """Run ``ss.simulate(target, **keywords)`` of ``model`` after checking every output path,
    write its files and report."""
    figures = get_model(model).time_stepping.figures
    if png and not figures:
        raise ParameterError(f"--png is invalid for model {model!r}: its run has no figure; "
                             "write the series with --npz")
    pngs = _figure_paths(png, figures)
    for name, path, suffix in (*(("--png", p, FIGURE_SUFFIXES) for p in pngs),
                               ("--npz", npz, ".npz"), ("output", json_path, ".json")):
        _check_output(name, path, suffix)
    run = _api().simulate(target, progress=progress, **keywords)
    _warn(run.warnings)
    written = _write_simulation(run, pngs, npz)
    if json_path is not None:
        _atomic_write(json_path, lambda p: p.write_text(json.dumps(run.to_dict(), indent=1)))
        written.append(str(json_path))
    return _report(as_json, run.to_dict(), run.summary, written)


BENCHMARK_FLAGS = {"rho": "fluid density (g/cm^3)", "mu": "dynamic viscosity (g/(cm s))",
                   "radius": "equilibrium radius R (cm)",
                   "sigma": "membrane stiffness (dyn/cm; the fibre: g cm/s^2; cochlea-tone: "
                            "g/(cm^2 s^2) at the base)",
                   "length": "basilar-membrane length L (cm; cochlea-tone)",
                   "lambda_c": "stiffness decay rate (1/cm; cochlea-tone)",
                   "l": "degree of the initial shape", "k": "order of the initial shape",
                   "m": "wavenumber of the fibre's shape (fibre problems)",
                   "epsilon": "initial amplitude A0 / R",
                   "omega": "forcing angular frequency (rad/s; parametric problems and the "
                            "tone of cochlea-tone)",
                   "margin": "tau = (1 -+ margin) tau_min (parametric problems)"}


def _benchmark_params(args: argparse.Namespace) -> dict[str, Any]:
    """The problem parameters given as flags (integers l, k; reals otherwise)."""
    return {k: (parse_int if k in ("l", "k", "m") else parse_real)(k, getattr(args, k))
            for k in BENCHMARK_FLAGS if getattr(args, k, None) is not None}


def cmd_benchmark(args) -> int:
    """benchmark list | show NAME | write NAME --out DIR | score NAME FILE [--png FILE]."""
    from .runner import benchmark as bench   # lazy: brings scipy and the solvers

    if args.action == "list":
        items = bench.listing()
        return _report(args.json, {"problems": items},
                       lambda: "\n".join(f"{i['name']}: {i['title']}" for i in items))
    params = _benchmark_params(args)
    if args.action == "show":
        text = bench.specification_text(args.name, **params)
        return _report(args.json, {"problem": args.name, "specification": text}, lambda: text)
    if args.action == "write":
        bench.benchmark_problem(args.name)
        out = _make_dir(args.out)
        for suffix in (".nc", ".csv"):
            _check_output("output", out / f"{args.name}{suffix}", suffix)
        ds = bench.benchmark(args.name, **params)
        paths = [out / f"{args.name}{suffix}" for suffix in (".nc", ".csv")]
        _atomic_write(paths[0], lambda p: bench.write_netcdf(ds, p))
        _atomic_write(paths[1], lambda p: bench.write_csv(ds, p))
        exact = {q: {k: ds[q].attrs[f"exact_{k}"] for k in ("growth_rate", "frequency")}
                 for q in bench.reference_columns(ds) if "exact_growth_rate" in ds[q].attrs}
        data = {"problem": args.name, "files": [str(p) for p in paths],
                "samples": int(ds.sizes[bench.axis(ds)]),
                **{k: ds.attrs[k] for k in ("peak_x_cm", "peak_error_cm") if k in ds.attrs},
                "exact_growth_rate": ds.attrs.get("exact_growth_rate"),
                "exact_frequency": ds.attrs.get("exact_frequency"), "exact": exact}
        return _report(args.json, data, lambda: f"{args.name}: {data['samples']} samples",
                       data["files"])
    _check_output("--png", args.png, FIGURE_SUFFIXES)
    bench.benchmark_problem(args.name)
    result, ds, user = bench.score(args.name, args.file, **params)
    written = []
    if args.png:
        from .plots.benchmark import score_figure

        _atomic_write(args.png, lambda p: score_figure(ds, user, p))
        written.append(args.png)
    return _report(args.json, result.to_dict(), result.summary, written)


def _benchmark_parser(sub) -> None:
    """The `benchmark` command and its actions list, show, write, score."""
    p = sub.add_parser("benchmark", help="benchmark problems for IB/FSI codes: specification, "
                       "reference data, score of a run")
    actions = p.add_subparsers(dest="action", required=True, parser_class=_Parser)
    q = actions.add_parser("list", help="the registered problems")
    q.add_argument("--json", action="store_true", help="print exactly one JSON object")
    for action, text in (("show", "the one-page specification of a problem"),
                         ("write", "write reference data NAME.nc and NAME.csv to --out DIR"),
                         ("score", "score your run (a CSV file) against the reference")):
        q = actions.add_parser(action, help=text)
        q.add_argument("name", help="problem name (see `spectralshell benchmark list`)")
        if action == "write":
            q.add_argument("--out", required=True, help="output directory (created if needed)")
        if action == "score":
            q.add_argument("file", help="your run: CSV with header t,<quantity>,... (t in s; "
                                        "cochlea-tone: x,envelope with x in cm; units as in "
                                        "`benchmark show`)")
            q.add_argument("--png", help=f"write reference and your run to {FIGURE_FILE}")
        for name, help_text in BENCHMARK_FLAGS.items():
            q.add_argument(f"--{name}", metavar="X", help=help_text)
        q.add_argument("--json", action="store_true", help="print exactly one JSON object")
    p.set_defaults(func=cmd_benchmark)


def _computation(sub, name: str, help: str, func, names: Sequence[str], configure, *,
                 skip: Sequence[str] = ()) -> None:
    """A computation subcommand ``name MODEL ...``: one sub-parser per model in ``names`` (from
    the registry) with that model's parameter flags and ``configure(parser, model)``'s options
    for this command, and --json."""
    p = sub.add_parser(name, help=help, description=f"{help}. Models: {', '.join(names)} "
                       f"('spectralshell {name} MODEL -h' lists a model's parameters).")
    per_model = p.add_subparsers(dest="model", metavar="MODEL", parser_class=_Parser,
                                 required=True)
    for model in names:
        q = per_model.add_parser(model, help=get_model(model).summary,
                                 description=f"{help}: {get_model(model).summary}")
        _model_flags(q, model, skip=skip)
        configure(q, model)
        q.add_argument("--json", action="store_true", help="print exactly one JSON object")
        q.set_defaults(func=func)


def _kind_flag(p: argparse.ArgumentParser) -> None:
    p.add_argument("--kind", default="both", choices=("both", "harmonic", "subharmonic"))


def _floquet_options(p: argparse.ArgumentParser, model: str) -> None:
    spec = get_model(model)
    _kind_flag(p)
    _solver_flags(p)
    _tau_max_flag(p)
    if spec.physical is not None:
        _physical_flags(p, dict(spec.physical.units), spec.physical.note)
    if spec.spatial:
        p.add_argument("--tol-spatial", dest="tol_spatial", metavar="X",
                       help="without --n-spatial: tolerance of tau_min in the number of spatial "
                            "modes (default 1e-3)")
        _max_seconds_flag(p)
    if model == "sphere":
        p.add_argument("--l-max", dest="l_max", metavar="L",
                       help="with --kappa an expression in theta, phi (non-uniform stiffness): "
                            "the degree truncation, 'auto' (default: raised until tau_min "
                            "settles to --tol-spatial) or an integer")
        p.add_argument("--tol-spatial", dest="tol_spatial", metavar="X",
                       help="with --l-max auto: tolerance of tau_min in the degree truncation "
                            "(default 1e-6)")
        _max_seconds_flag(p)


def _tongues_options(p: argparse.ArgumentParser, model: str) -> None:
    _kind_flag(p)
    _solver_flags(p)
    p.add_argument("--kappa", help="range START:STOP:NUM, e.g. 0:3:301")
    _tau_max_flag(p)
    p.add_argument("--png", help=f"write the diagram to {FIGURE_FILE}")
    p.add_argument("--csv", help="write points kind,kappa,tau to a *.csv file (an existing file is "
                                 "replaced)")
    p.add_argument("--npz", help="write arrays to a *.npz file (an existing file is replaced)")
    p.add_argument("--no-tips", action="store_true", help="do not locate finger tips")
    p.add_argument("--no-boundaries", action="store_true",
                   help="do not trace the boundaries as curves (the diagram shows the grid's "
                   "points; faster)")
    p.add_argument("--workers", type=int, default=None, help="processes (default: all cores)")
    _max_points_flag(p)


def _exponents_options(p: argparse.ArgumentParser, model: str) -> None:
    _solver_flags(p)
    p.add_argument("--tau", help="forcing amplitude")
    p.add_argument("--count", help="number of least-damped exponents listed (default: all found)")
    if model == "sphere":
        p.add_argument("--l-max", dest="l_max", metavar="L",
                       help="with --kappa an expression in theta, phi (non-uniform stiffness): "
                            "the degree truncation, 'auto' (default: raised until the least "
                            "damped exponent settles to 1e-6) or an integer")
        _max_seconds_flag(p)


def _stability_options(p: argparse.ArgumentParser, model: str) -> None:
    _kind_flag(p)
    _solver_flags(p)
    p.add_argument("--tau", help="forcing amplitude")
    p.add_argument("--m", help="degrees, a range START:STOP, e.g. 2:6")


def _modes_options(p: argparse.ArgumentParser, model: str) -> None:
    spec = get_model(model)
    p.add_argument("--count", help="number of least-damped modes (default: all)")
    p.add_argument("--precision", help="digits of an mpmath polish, e.g. 30")
    p.add_argument("--zeta", help="shorthand for --kappa 1 --nu ZETA")
    if spec.mode_inputs:
        _physical_flags(p, dict(spec.mode_inputs), "instead of --kappa and --nu; rates then in "
                                                   "s^-1")


def _response_options(p: argparse.ArgumentParser, model: str) -> None:
    spec = get_model(model)
    p.add_argument("--kind", default="tone", choices=("tone", "harmonic", "subharmonic"),
                   help="tone: passive response to a load at the base; harmonic/subharmonic: the "
                        "Floquet solution at tau_min (thesis 5.5)")
    if spec.physical is not None:
        _physical_flags(p, dict(spec.physical.units), spec.physical.note)
    _solver_flags(p)
    _max_seconds_flag(p)
    p.add_argument("--png", help=f"write the envelope and profile to {FIGURE_FILE}")


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="spectralshell", description=__doc__.splitlines()[0])
    parser.add_argument("--version", action="version", version=f"spectralshell {__version__}")
    sub = parser.add_subparsers(dest="command", parser_class=_Parser, required=True)
    every = models()
    _computation(sub, "floquet", "marginal forcing amplitudes tau (harmonic/subharmonic)",
                 cmd_floquet, every, _floquet_options)
    _computation(sub, "tongues", "Ince-Strutt diagram over a kappa range", cmd_tongues,
                 [m for m in every if "kappa" in param_names(m)], _tongues_options,
                 skip=("kappa",))
    _computation(sub, "exponents", "Floquet exponents gamma at a forcing amplitude tau",
                 cmd_exponents, every, _exponents_options)
    _computation(sub, "stability", "which degrees m are unstable at a forcing amplitude tau",
                 cmd_stability, [m for m in every if "m" in param_names(m)], _stability_options,
                 skip=("m",))
    _computation(sub, "modes", "natural modes gamma (decay rate, frequency) at tau = 0",
                 cmd_modes, models_with("modal_system", "mode_family"), _modes_options)
    _computation(sub, "response", "BM displacement envelope for a pure tone (thesis 5.5)",
                 cmd_response, models_with("response"), _response_options)

    p = sub.add_parser("lp", help="nonlinear frequency coefficient c (Lindstedt-Poincare, thesis 7.3)")
    p.add_argument("--m", help="degree of the initial shape, 2..8")
    p.add_argument("--k", default="0", help="order k, |k| <= m (real harmonic)")
    p.add_argument("--volume", default="reference", choices=("reference", "literal"),
                   help="enclosed volume: the unit sphere's (default) or that of 1 + eps Y exactly")
    p.add_argument("--check", action="store_true", help="also run the direct nonlinear solve")
    p.add_argument("--json", action="store_true", help="print exactly one JSON object")
    p.set_defaults(func=cmd_lp)

    p = sub.add_parser("figure", help="reproduce a thesis figure (PNG + JSON data)")
    p.add_argument("name", help="a thesis figure, e.g. fig-6.3; 'list' prints every name with "
                                "what it shows")
    p.add_argument("--out", default=".", help="output directory (default: the current one)")
    p.add_argument("--workers", type=int, default=None,
                   help="processes for the figure sweeps (default: all cores)")
    p.set_defaults(func=cmd_figure)

    p = sub.add_parser("validate", help="run the validation cases; write report.md, report.html and PNGs "
                                        "(exit 1 if any case fails)")
    p.add_argument("--out", default="validation-report", help="output directory (default validation-report)")
    p.add_argument("--quick", action="store_true", help="only the quick cases (well under 2 minutes)")
    p.add_argument("--workers", default=None, help="processes for the figure sweeps (default: all cores)")
    p.set_defaults(func=cmd_validate)

    p = sub.add_parser("demo", help="run the embedded default scene")
    p.add_argument("--out", default="demo-output", help="output directory (default demo-output)")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_demo)

    p = sub.add_parser("run", help="run a scene TOML file (a scene with a [grid] runs as a "
                       "resumable sweep, one with [initial] or [simulate] as simulate FILE)")
    p.add_argument("scene")
    p.add_argument("--out", default=None, help="output directory (default: the scene's)")
    _max_seconds_flag(p)
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("sweep", help="parameter sweep of a scene with a [grid] (resumable .zarr / .nc)")
    p.add_argument("scene", help="scene TOML with model, ask, [params] and [grid]")
    p.add_argument("--out", required=True, help="PATH.zarr (chunk by chunk, resumable) or PATH.nc")
    p.add_argument("--executor", choices=("serial", "processes", "dask"), default=None,
                   help="default: processes, or dask when --scheduler is given")
    p.add_argument("--workers", type=int, default=None,
                   help="processes or LocalCluster workers (default: all cores)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS|local",
                   help="Dask scheduler tcp://HOST:PORT, or 'local' for a LocalCluster")
    _max_points_flag(p)
    _max_seconds_flag(p)
    p.add_argument("--json", action="store_true",
                   help='print exactly one object {"points", "computed", "skipped", "damaged", '
                        '"outdated", "uncertified", "out", "seconds"} (exit 1 if uncertified > 0)')
    p.set_defaults(func=cmd_sweep)

    stepped = models_with("time_stepping")
    p = sub.add_parser("simulate", help="time-step a model (spectral IMEX): the time series and "
                       "fitted growth rates and frequencies",
                       description="Time-step a model: " + "; ".join(
                           f"{m} ({', '.join(_flag(k) for k in stepping_keywords(m))})"
                           for m in stepped) + ".")
    p.add_argument("target", help=f"a model that can be time-stepped ({', '.join(stepped)}; "
                   "then give the flags below) or a simulation scene TOML file of one")
    for name, text in _simulation_flags().items():
        p.add_argument(_flag(name), dest=name, metavar="X", help=text)
    p.add_argument("--png", help=f"write the amplitudes against time to {FIGURE_FILE} (fibre, "
                   "cochlea: the fitted series on a log axis with the fitted growth and the "
                   "leading Floquet exponent's slope; the sphere: every mode, and the membrane "
                   "shape in NAME_shape with the same suffix)")
    p.add_argument("--npz", help="write the trajectory to a *.npz file (an existing file is "
                                 "replaced)")
    p.add_argument("--json", action="store_true", help="print exactly one JSON object")
    p.set_defaults(func=cmd_simulate)

    _benchmark_parser(sub)

    p = sub.add_parser("plot", help="draw a stored sweep (.zarr or .nc) as PNG")
    p.add_argument("store", help="a sweep written by `spectralshell sweep --out`")
    p.add_argument("--png", required=True, help=f"write the picture to {FIGURE_FILE}")
    p.set_defaults(func=cmd_plot)
    return parser


def _option_flags(parser: argparse.ArgumentParser) -> dict[str, str]:
    """API keyword -> CLI flag of every option of ``parser`` and its subcommands."""
    flags: dict[str, str] = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for child in action.choices.values():
                flags.update(_option_flags(child))
        elif action.option_strings and action.option_strings[-1].startswith("--"):
            flags[action.dest] = action.option_strings[-1]
    return flags


_KEYWORD = re.compile(r"(?<![\w.-])([a-z][a-z0-9_]*)=(?!=)")


def _as_flags(message: str, parser: argparse.ArgumentParser | None) -> str:
    """A library message in the CLI's words: each API keyword ``name=`` that is an option of
    ``parser`` (None: no parser was built; the message is kept) becomes its flag
    (``tau_max=0.5`` -> ``--tau-max 0.5``, ``tol=,`` -> ``--tol,``); messages name API
    parameters (issue 24), the CLI names its flags. The option map is made only here, when
    an error is reported."""
    flags = {} if parser is None else _option_flags(parser)

    def flag(match: re.Match) -> str:
        name = match.group(1)
        if name not in flags:
            return match.group(0)
        rest = message[match.end():match.end() + 1]
        return flags[name] + (" " if rest and not rest.isspace() and rest not in ",;)" else "")

    return _KEYWORD.sub(flag, message)


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of ``spectralshell`` and ``python -m spectralshell``."""
    if (sys.argv[1:] if argv is None else list(argv)) == ["--version"]:
        print(f"spectralshell {__version__}")  # before the parser, which loads every model
        return 0
    parser = None
    try:
        load_entry_points()
        parser = build_parser()
        args = parser.parse_args(argv)
        return args.func(args)
    except ConvergenceError as exc:
        print(f"spectralshell: not converged: {_as_flags(str(exc), parser)}", file=sys.stderr)
        return 1
    except (ParameterError, SpectralShellError) as exc:
        print(f"spectralshell: error: {_as_flags(str(exc), parser)}", file=sys.stderr)
        return 2
    except MemoryError:
        print("spectralshell: out of memory: reduce the problem size (grid points, truncation, "
              "steps)", file=sys.stderr)
        return 1
    except ArithmeticError as exc:  # validation should make this impossible: a bug to report
        print(f"spectralshell: internal limit reached ({type(exc).__name__}: {exc}); no result "
              "was produced; please report the command line", file=sys.stderr)
        return 1
    except OSError as exc:  # the file system failed during the run (disk full, removed directory)
        print(f"spectralshell: cannot complete: {exc.strerror or exc}"
              + (f": {exc.filename!r}" if exc.filename else ""), file=sys.stderr)
        return 1
    except KeyboardInterrupt as exc:
        print(f"spectralshell: interrupted{_kept(exc, argv)}", file=sys.stderr)
        return 130


def _kept(exc: KeyboardInterrupt, argv: Sequence[str] | None) -> str:
    """What an interrupted sweep kept, and the command that resumes it ('' for another
    Ctrl-C)."""
    if not isinstance(exc, SweepInterrupted):
        return ""
    if exc.out is None:
        return f": {exc}"
    command = shlex.join(["spectralshell", *(sys.argv[1:] if argv is None else argv)])
    return f": {exc}; resume with: {command}"
