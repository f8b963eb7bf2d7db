"""``colonna`` command line.

    colonna rigid     time history of a rocking block (solid or cracked with collars)
    colonna spectrum  overturning spectrum (mode map) with or without collars
    colonna design    collar design numbers (corrected Eq. 22-24) and the design chart
    colonna collar    one collar through imposed end displacements (the collar test bench)
    colonna fem       2D finite-element contact model of a study file
    colonna study     a study file of any kind (its [study] kind) with an HTML report
    colonna schema    the study file's keys (JSON Schema, or Markdown for docs/study-file.md)
    colonna warmup    compile the kernels and measure the FEM's cost on this machine
    colonna validate  the Zhang & Makris validation block (make demo)
    colonna fragility the SDOF's fragility over a record suite, fast

Bad input ends with one line ``colonna: error: ...`` naming the parameter (a study file: one
line for each of its errors, all at once), exit status 2; so do results in --out saved from other
inputs and a run whose numbers are not an answer (:data:`EXIT_STATUS`).
"""

from __future__ import annotations

import argparse
import importlib
import json
import math
import signal
import sys
import threading
import warnings
from pathlib import Path

import numpy as np

from ..core.collar import Collar
from ..core.constants import STEEL_E, STEEL_FY
from ..core.errors import (
    ColonnaError,
    InputError,
    NumericalFailure,
    StaleResultsError,
)
from ..core.ground import (
    NO_MOTION,
    PULSE_KINDS,
    GroundMotion,
    RecordNote,
    read_record,
    weak_record_note,
)
from ..core.motion import Motion
from ..rigid.block import pulse_from_ratios
from . import schema
from .options import add_block_options, add_collar_option, block_from_args, collars_from_args
from .output import FolderInUse, write_csv, write_json
from .units import unit_of


class _Parser(argparse.ArgumentParser):
    """argparse with the project's one-line error format (no usage block)."""

    def error(self, message):
        self.exit(2, f"colonna: error: {message} (see '{self.prog} --help')\n")


# --- shared option groups ---------------------------------------------------------------------


def _add_multibody_options(parser) -> None:
    g = parser.add_argument_group("multibody model (--model multibody)")
    g.add_argument(
        "--cracked",
        action="store_true",
        help="two half columns, each the block given (implied by --collars)",
    )
    g.add_argument(
        "--friction", type=float, help="Coulomb coefficient at the base and the crack (default 0.7)"
    )
    g.add_argument(
        "--crack-friction",
        type=float,
        help="Coulomb coefficient along the crack (default: --friction)",
    )


def _multibody_options(args):
    """The multibody solvers' contact (:class:`colonna.rigid.multibody.MultibodyContact`), None
    for another model; an error if a contact option is given for another model."""
    given = [
        name
        for name in ("cracked", "friction", "crack_friction")
        if getattr(args, name) not in (None, False)
    ]
    if args.model != "multibody":
        if given:
            raise InputError(
                f"--{given[0].replace('_', '-')} applies to --model multibody "
                f"only (the {args.model} model has no contact)"
            )
        return None
    from ..rigid.multibody import DEFAULT_FRICTION, MultibodyContact

    return MultibodyContact(
        cracked=bool(args.cracked or args.collars),
        friction=DEFAULT_FRICTION if args.friction is None else args.friction,
        crack_friction=args.crack_friction,
    )


SIGNIFICANT_DIGITS = 4


def format_value(key: str, value) -> str:
    """A summary value for people: numbers to SIGNIFICANT_DIGITS with their unit (stresses in
    MPa, forces in kN: :func:`colonna.studies.units.unit_of`), counts as integers, words as
    they are."""
    if value is None:
        return "none"
    if isinstance(value, (bool, np.bool_, str)):
        return str(value)
    if isinstance(value, (int, np.integer)) and not unit_of(key)[0]:
        return str(int(value))
    if isinstance(value, (int, float, np.integer, np.floating)):
        unit, factor = unit_of(key)
        text = f"{float(value) * factor:.{SIGNIFICANT_DIGITS}g}"
        if "e+" in text and abs(float(text)) < 1e6:  # 11630, not 1.163e+04
            text = f"{float(text):.0f}"
        return f"{text} {unit}" if unit else text
    return str(value)


def kernels_cached(kernels) -> bool:
    """Whether every numba kernel given (``cache=True`` dispatchers) is compiled in this process
    or in numba's on-disk cache for this source, numba version and processor, so that calling
    it compiles nothing. Where numba's cache cannot be read, True: nothing to announce."""
    for kernel in kernels:
        if kernel.overloads:
            continue
        try:
            cache = kernel._cache
            codegen = kernel.targetctx.codegen()
            overloads = cache._cache_file._load_index()  # {} when missing or stale
            wanted = cache._index_key(None, codegen)[1:]  # processor, bytecode hashes
        except Exception:  # numba's cache internals moved: say nothing rather than guess
            continue
        if not any(key[1:] == wanted for key in overloads):
            return False
    return True


def _announce_compilation(kernels, what: str, seconds: int) -> None:
    """One line on stderr before a run that will first compile its numba kernels."""
    if not kernels_cached(kernels):
        print(
            f"colonna: compiling the {what} (first run on this machine, about {seconds} s; "
            "cached afterwards)",
            file=sys.stderr,
            flush=True,
        )


def _multibody_kernels(spectrum: bool = False) -> list:
    from .models import kernels

    return kernels("multibody spectrum" if spectrum else "multibody")


def _study_kernels(study) -> tuple[list, str]:
    """The numba kernels a study runs, announced before their first compilation, and their
    name: the FEM's and the multibody's, a fragility's only those of its models (an SDOF-only
    one none of them, so that no run announces a compilation it never does): the gateway to the
    models names them (:func:`studies.models.kernels`)."""
    from .models import kernels as of_models

    fragility = study.spec.fragility
    fem = fragility is None or "fem" in fragility.models
    multibody = fragility is None or "multibody" in fragility.models
    kernels = of_models(*(m for m, used in (("fem", fem), ("multibody", multibody)) if used))
    names = [name for name, used in (("FEM", fem), ("multibody", multibody)) if used]
    return kernels, " and ".join(names) + " kernels"


def _emit(args, summary: dict | None) -> None:
    """Print a command's summary: one JSON object at full precision with --json, else one
    ``key  value unit`` line per scalar (lists and tables are left to --json and --out)."""
    if summary is None:  # the command printed its own output
        return
    if args.json:
        print(json.dumps(summary))
    else:
        for key, value in summary.items():
            if not isinstance(value, (list, dict)):
                print(f"{key:28s} {format_value(key, value)}")


# --- colonna rigid ------------------------------------------------------------------------------


def _cmd_rigid(args) -> dict:
    from ..rigid.solve import rock

    block = block_from_args(args)
    collars = collars_from_args(args)
    sdof_model = "linear" if args.model == "linear" else "nonlinear"  # a_uplift of the ratios
    if args.record is not None:
        if args.omega_ratio is not None or args.amplitude_ratio is not None:
            raise InputError("give either --record or --omega-ratio/--amplitude-ratio")
        ground = read_record(args.record, g=block.g).scaled(args.scale)
    else:
        if args.omega_ratio is None or args.amplitude_ratio is None:
            raise InputError(
                "a pulse needs --omega-ratio and --amplitude-ratio (or give --record FILE)"
            )
        ground = pulse_from_ratios(
            block, args.pulse, args.omega_ratio, args.amplitude_ratio, sdof_model
        )
    vertical: GroundMotion = NO_MOTION
    if args.vertical_record is not None:
        vertical = read_record(args.vertical_record, g=block.g).scaled(args.vertical_scale)
    elif args.record is not None:  # a record too weak to rock the block: said, not refused
        note = weak_record_note(
            ground,
            block.uplift_acceleration(sdof_model),
            what=f"record file {args.record.name}",
            scale=args.scale,
            scale_name="--scale",
            in_m_s2=args.record.suffix.lower() != ".at2",
            g=block.g,
        )
        if note is not None:
            warnings.warn(note, RecordNote, stacklevel=1)
    contact = _multibody_options(args)
    if contact is not None:
        from ..rigid.multibody import history_columns, rock_multibody

        _announce_compilation(_multibody_kernels(), "multibody kernels", 30)
        result = rock_multibody(
            block,
            Motion(ground, duration=args.duration, vertical=vertical),
            collars,
            contact=contact,
        )
        columns = history_columns(result)
    else:
        result = rock(
            block,
            Motion(ground, duration=args.duration, vertical=vertical),
            collars,
            model=args.model,
        )
        columns = {"t": result.time, "theta": result.theta, "theta_dot": result.theta_dot}
        for k, hist in enumerate(result.collar_histories, start=1):
            columns[f"collar_{k}_axial_force"] = hist.axial_force
            columns[f"collar_{k}_end_moment"] = hist.end_moment
            columns[f"collar_{k}_stress"] = hist.stress
    summary = result.summary()
    summary["uplift_acceleration"] = block.uplift_acceleration(sdof_model)
    if args.out:
        out = Path(args.out)
        columns["ground_acceleration"] = ground.acceleration(result.time)
        write_csv(out / "history.csv", columns)
        impacts = {
            "t": result.impact_times,
            "theta_dot_before": result.impact_velocity_before,
            "theta_dot_after": result.impact_velocity_after,
        }
        if contact is not None:
            impacts["body"] = result.impact_bodies
        write_csv(out / "impacts.csv", impacts)
        write_json(out / "summary.json", summary)
        from ..rigid.plotting import plot_history

        plot_history(result, out / "history.png")
    return summary


# --- colonna spectrum ---------------------------------------------------------------------------


def _cmd_spectrum(args) -> dict:
    from ..rigid.spectrum import overturning_spectrum, parse_range

    block = block_from_args(args)
    collars = collars_from_args(args)
    omegas = parse_range(args.omega_ratios, "--omega-ratios")
    amplitudes = parse_range(args.amplitude_ratios, "--amplitude-ratios")
    contact = _multibody_options(args)
    if contact is not None:
        from ..rigid.multibody import multibody_spectrum

        _announce_compilation(_multibody_kernels(spectrum=True), "multibody kernels", 30)
        spectrum = multibody_spectrum(
            block, omegas, amplitudes, collars, contact=contact, pulse=args.pulse
        )
    else:
        spectrum = overturning_spectrum(
            block, omegas, amplitudes, collars, model=args.model, pulse=args.pulse
        )
    summary = spectrum.to_dict()
    if args.out:
        out = Path(args.out)
        write_json(out / "spectrum.json", summary)
        write_csv(
            out / "minimum_overturning_amplitude.csv",
            {
                "omega_ratio": spectrum.omega_ratios,
                "amplitude_ratio": spectrum.minimum_overturning_amplitude(),
            },
        )
        from ..rigid.plotting import plot_spectrum

        plot_spectrum(spectrum, out / "spectrum.png")
    if not args.json:
        counts = np.bincount(spectrum.codes.ravel(), minlength=3)
        short = {
            "points": int(spectrum.codes.size),
            "safe": int(counts[0]),
            "after-impact": int(counts[1]),
            "without-impact": int(counts[2]),
        }
        if spectrum.collar_yields is not None:  # "safe" is the overturning, not the collars
            yields = np.asarray(spectrum.collar_yields, dtype=bool)
            short["collars_yielded"] = int(yields.sum())
            short["safe_with_collars_yielded"] = int((yields & (spectrum.codes == 0)).sum())
        return {**short, "seconds": spectrum.seconds}
    return summary


# --- colonna design -----------------------------------------------------------------------------


def _check_plausible_collar(args) -> None:
    """The collar flags of colonna design against a collar file's plausible ranges
    (:func:`studies.schema.implausible`): a unit slip (--collar-fy 275, meant MPa) is an error
    naming the flag and the likely unit, unless its key is in --intended."""
    given = {
        key: getattr(args, f"collar_{key}")
        for key in ("t", "h", "length", "E", "fy")
        if getattr(args, f"collar_{key}") is not None
    }
    lines = [
        line.replace("collar[1].", "--collar-")
        for line, _ in schema.implausible(
            schema.CollarFile, {"collar": [given]}, list(args.intended), "--intended"
        )
    ]
    if lines:
        raise InputError("\n".join(lines))


def _cmd_design(args) -> dict:
    from ..rigid.design import design_chart, design_collars

    block = block_from_args(args)
    block.require_mass("the collar design (give --mass or --density)")
    _check_plausible_collar(args)
    collar = Collar(
        y=block.h,
        t=args.collar_t,
        h=args.collar_h,
        length=args.collar_length,
        E=args.collar_E,
        fy=args.collar_fy,
    )
    if (args.ag is None) == (args.ag_ratio is None):
        raise InputError(
            "give the design pulse peak with exactly one of --ag (m/s^2) or --ag-ratio (a_g / g)"
        )
    a_g = args.ag if args.ag is not None else args.ag_ratio * block.g
    design = design_collars(block, collar, a_g)
    summary = design.to_dict()
    summary.update(
        {"alpha": block.alpha, "b": block.b, "h": block.h, "collar_yield_stress": collar.fy}
    )
    if args.out:
        out = Path(args.out)
        write_json(out / "design.json", summary)
        if args.density is not None:
            thickness = args.thickness if args.thickness is not None else math.pi * block.b
            alphas = np.linspace(0.05, 0.5, 46)
            ratios = np.linspace(0.05, 1.0, 39)
            k = design_chart(block.b, args.density, thickness, collar, alphas, ratios, block.g)
            write_csv(
                out / "design_chart.csv",
                {
                    "alpha": np.repeat(alphas, ratios.size),
                    "ag_over_g": np.tile(ratios, alphas.size),
                    "required_stiffness": k.ravel(),
                },
            )
            from ..rigid.plotting import plot_design_chart

            plot_design_chart(
                alphas,
                ratios,
                k,
                out / "design_chart.png",
                design=(a_g / block.g, block.alpha, design.required_stiffness),
            )
    return summary


# --- colonna fem --------------------------------------------------------------------------------


def resolve_study(name_or_path: str) -> Path:
    """A study file path, or the name of a study shipped in studies/ (default, ...)."""
    path = Path(name_or_path)
    if path.is_file():
        return path
    shipped = Path(__file__).parent / f"{name_or_path}.toml"
    if shipped.is_file():
        return shipped
    names = sorted(p.stem for p in Path(__file__).parent.glob("*.toml"))
    raise InputError(f"study {name_or_path!r} is neither a file nor one of: {', '.join(names)}")


def _cmd_fem(args) -> dict:
    from ..fem.solver import unreliable_reason
    from .models import run_fem
    from .study import load
    from .work import fem_work, require_bounded_work

    # (no compile notice here: the run's own checks (stable step, mesh, output folder) come
    # inside run_fem, and a notice must not come before an input error)
    study = load(resolve_study(args.study)).fem
    require_bounded_work(fem_work(study), long=args.long, what=f"{args.study}: this run")
    result = run_fem(study, replicas=1, out_dir=args.out, progress=True)[0]
    why = unreliable_reason([result.summary])  # a blow-up, or a balance past its limit
    if why is not None:
        raise NumericalFailure(
            f"the run is unreliable, its numbers are not an answer: {why}; its files are "
            f"kept in {args.out} to be looked at"
        )
    return result.summary


# --- colonna study ------------------------------------------------------------------------------


def _cmd_study(args) -> dict:
    from .driver import check_study_file, run_study_file
    from .executor import available_cores, default_workers
    from .kinds import KINDS, study_options, take_options

    study = check_study_file(resolve_study(args.study))  # read and validated once, here
    kind = KINDS[study.kind]
    workers = args.workers if args.workers is not None else default_workers()
    cores = available_cores()
    if not 1 <= workers <= cores:  # more processes than cores only slows every case down
        raise InputError(
            f"--workers = {workers} is outside 1..{cores} "
            f"(this machine has {cores} core{'s' if cores > 1 else ''})"
        )
    given = {name: getattr(args, name.replace("-", "_")) for name in study_options()}
    options = take_options(study.kind, {k: v for k, v in given.items() if v is not None})
    if args.paper is not None and not args.pdf:
        raise InputError("--paper sets the PDF's paper: give it with --pdf")
    if args.pdf:
        from .pdf import require_browser, require_paper

        require_paper(args.paper or "a4")
        require_browser()
    from .executor import RunOptions, before_computing

    kernels, what = _study_kernels(study)

    def announce():
        _announce_compilation(kernels, what, 60)

    with before_computing(announce):
        summary = run_study_file(
            study,
            Path(args.out),
            long=args.long,
            options=options,
            run_options=RunOptions(workers=workers, scheduler=args.scheduler, force=args.force),
        )
    if args.pdf:
        from .pdf import write_pdf

        pdf = write_pdf(
            Path(args.out) / "index.html", Path(args.out) / "report.pdf", args.paper or "a4"
        )
        print(f"[study] PDF: {pdf}", file=sys.stderr, flush=True)
    if args.json:
        return summary
    return short_summary(kind.short, summary, Path(args.out) / "index.html")


def short_summary(keys, summary: dict, report: Path) -> dict:
    """What ``colonna study`` prints of a kind's summary, the report's first screen in its
    words (``keys``, a kind's ``short``): "outcome", each model's motion, then each question
    with its answer and qualifier (a stress answer of a column that overturns reads 'no
    (until overturning at t = ...)', never a bare 'no'); "design", the fragility's probability
    of each limit state at the design intensity, per model; "answer", the collar layout's
    question and its one-sentence answer. Internal keys stay in
    summary.json."""
    short: dict = {"report": str(report)}
    for key in keys:
        value = summary.get(key)
        if key == "outcome" and value:  # the report's opening, in words
            for m in value["models"]:
                time = m.get("overturn_time")
                short[m["model"]] = (
                    m["motion"]
                    + (f" (run stops at t = {time:.3f} s)" if time is not None else "")
                    + (f"; {m['caveat']}" if m.get("caveat") else "")  # why it is no pass
                )
            for answer in value.get("answers", ()):
                qualifier = "; ".join(
                    w
                    for w in (answer.get("qualifier") or answer.get("why"), answer.get("caveat"))
                    if w
                )
                short[answer["question"]] = answer["answer"] + (
                    f" ({qualifier})" if qualifier else ""
                )
        elif key == "design" and value:
            short.update(_design_probabilities(summary))
        elif key == "answer" and value:  # the collar layout: its question, its sentence
            short["Which collars does this column need?"] = value
    return short


# a fragility's intensity measures (colonna.core.intensity.IntensityMeasures) in words
INTENSITY_WORDS = {
    "pga": "PGA",
    "pgv": "PGV",
    "pgd": "PGD",
    "arias": "Arias intensity",
    "cav": "CAV",
    "d5_95": "duration D5-95",
    "pga_rocking": "PGA / (g tan alpha)",
    "pgv_rocking": "PGV p / (g tan alpha)",
}


def _design_probabilities(summary: dict) -> dict:
    """A fragility's first screen in words: per limit state, the question 'Probability of
    ... at IM = x?' and each model's answer as its report's table gives it; with a hazard,
    then 'Mean annual frequency of ... at the site?' and each model's lambda, return period
    and probability in T years with their intervals and what of lambda lies beyond the data,
    as its risk table gives them (issue 50)."""
    from .fragility.report import MODEL_NAMES, design_rows, risk_rows

    unit = summary.get("intensity_unit")
    at = (
        f"{INTENSITY_WORDS.get(summary['intensity'], summary['intensity'])} = "
        f"{summary['design_intensity']:.4g}{f' {unit}' if unit and unit != '-' else ''}"
    )
    short = {
        f"Probability of {row['state']} at {at}?": "; ".join(
            f"{MODEL_NAMES.get(model, model)}: {cell['text']}"
            + (f" ({cell['note']})" if cell.get("note") else "")
            for model, cell in zip(summary["models"], row["cells"])
        )
        for row in design_rows(summary)
    }
    for row in risk_rows(summary):
        years = f"{summary['hazard']['years']:g}"
        answer = row.get("text") or (
            f"{row['frequency']} per year, return period {row['period']} years, "
            f"P in {years} years {row['probability']}"
            + (f" ({'; '.join(row['words'])})" if row["words"] else "")
        )
        question = f"Mean annual frequency of {row['state']} at the site?"
        short[question] = "; ".join(
            w for w in (short.get(question), f"{row['model']}: {answer}") if w
        )
    return short


# --- colonna schema ------------------------------------------------------------------------------


def _cmd_schema(args) -> None:
    """Prints the JSON Schema (indented, for editors) or its Markdown key list itself."""
    from .schema import json_schema, markdown

    sys.stdout.write(markdown() if args.markdown else json.dumps(json_schema(), indent=2) + "\n")


# --- colonna validate ---------------------------------------------------------------------------


def _cmd_validate(args) -> dict:
    from .zhang_makris import zhang_makris_validation

    return zhang_makris_validation(Path(args.out), progress=not args.json)


# --- colonna warmup -----------------------------------------------------------------------------


def _cmd_warmup(args) -> None:
    from .warmup import warm

    print("colonna: compiling the kernels into numba's cache (once per install)", file=sys.stderr)
    seconds = warm(main, say=lambda line: print(line, file=sys.stderr))
    print(f"colonna: kernels compiled and cached in {seconds:.0f} s", file=sys.stderr)
    from .cost import save_calibration
    from .warmup import calibrate

    model, measurements = calibrate()
    path = save_calibration(model, measurements)
    print(
        "colonna: FEM cost model measured on this machine (for the estimates of time): "
        f"{model.group_step * 1e6:.2g} us + {model.group_node_step * 1e9:.2g} ns a node per "
        f"state-step in a batch, {model.single_step * 1e6:.2g} us + "
        f"{model.single_node_step * 1e9:.2g} ns alone; saved in {path}",
        file=sys.stderr,
    )


# --- parser -------------------------------------------------------------------------------------


def _add_long_option(parser) -> None:
    from .work import WORK_LIMIT_SECONDS

    parser.add_argument(
        "--long",
        action="store_true",
        help=f"run FEM work estimated at more than {WORK_LIMIT_SECONDS / 3600:g} h of CPU "
        "(refused without it, before anything is written)",
    )


def _add_rigid_parser(sub) -> None:
    """`colonna rigid`: one rocking time history (SDOF or multibody)."""
    p = sub.add_parser(
        "rigid",
        help="rocking time history of a rigid block, or of a cracked column's two halves with "
        "collars (SDOF or multibody)",
    )
    add_block_options(p)
    g = p.add_argument_group("ground motion")
    g.add_argument("--pulse", choices=PULSE_KINDS, default="sine")
    g.add_argument("--omega-ratio", type=float, help="Omega / p")
    g.add_argument(
        "--amplitude-ratio",
        type=float,
        help="a_p / a_uplift (uplift: g tan(alpha) nonlinear, g alpha linear), >= 1",
    )
    g.add_argument(
        "--record",
        type=Path,
        help="accelerogram: PEER .AT2 or ESM ASCII (units from its header), or two columns "
        "t (s), a (m/s^2)",
    )
    g.add_argument("--scale", type=float, default=1.0, help="scale factor on the record")
    g.add_argument(
        "--vertical-record", type=Path, help="vertical accelerogram (upward positive), as --record"
    )
    g.add_argument(
        "--vertical-scale", type=float, default=1.0, help="scale factor on the vertical record"
    )
    p.add_argument("--duration", type=float, help="end time (s); default end of motion + 20/p")
    add_collar_option(p)
    _add_multibody_options(p)
    p.add_argument(
        "--out", type=Path, help="write history.csv, impacts.csv, summary.json, history.png here"
    )
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_cmd_rigid)


def _add_spectrum_parser(sub) -> None:
    """`colonna spectrum`: an overturning spectrum (mode map)."""
    p = sub.add_parser(
        "spectrum", help="overturning spectrum (mode map) of a rigid block, with or without collars"
    )
    add_block_options(p)
    p.add_argument("--pulse", choices=PULSE_KINDS, default="sine")
    p.add_argument("--omega-ratios", required=True, help="START:STOP:N of Omega / p")
    p.add_argument("--amplitude-ratios", required=True, help="START:STOP:M of a_p / a_uplift")
    add_collar_option(p)
    _add_multibody_options(p)
    p.add_argument("--out", type=Path, help="write spectrum.json, spectrum.png, CSV here")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_spectrum)


def _add_design_parser(sub) -> None:
    """`colonna design`: the collar design (corrected Eq. 22-24)."""
    p = sub.add_parser("design", help="collar design (corrected Eq. 22-24)")
    add_block_options(p)
    g = p.add_argument_group("collar section and design pulse")
    g.add_argument("--collar-t", type=float, required=True, help="section thickness t_c (m)")
    g.add_argument("--collar-h", type=float, required=True, help="section height h_c (m)")
    g.add_argument("--collar-length", type=float, help="collar length L (m), default 4b")
    g.add_argument(
        "--collar-E", type=float, default=STEEL_E, help=f"steel E (Pa), default {STEEL_E:g}"
    )
    g.add_argument(
        "--collar-fy",
        type=float,
        default=STEEL_FY,
        help=f"steel f_y (Pa), default {STEEL_FY:g} (S235)",
    )
    g.add_argument("--ag", type=float, help="design peak ground acceleration (m/s^2)")
    g.add_argument("--ag-ratio", type=float, help="design peak ground acceleration / g")
    g.add_argument(
        "--intended",
        nargs="+",
        default=[],
        metavar="KEY",
        help="collar keys (collar.t, collar.fy, ...) whose values outside their plausible "
        "range are meant",
    )
    p.add_argument("--out", type=Path, help="write design.json and (with --density) the chart")
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_design)


def _add_collar_parser(sub) -> None:
    """`colonna collar`: the collar bench (studies/collar_bench.py)."""
    p = sub.add_parser("collar", help="one collar through imposed end displacements (bench)")
    collar_bench = importlib.import_module(f"{__package__}.collar_bench")
    collar_bench.add_arguments(p)
    p.set_defaults(func=collar_bench.run_command)


def _add_fem_parser(sub) -> None:
    """`colonna fem`: one FEM run of a study file, without a report."""
    p = sub.add_parser(
        "fem",
        help="one 2D finite-element contact run of a study file's column and ground motion, "
        "without the rigid models or a report",
    )
    p.add_argument("study", help="study file (TOML) or the name of a shipped study")
    p.add_argument(
        "--out",
        type=Path,
        required=True,
        help="write summary.json, history.csv and VTU/XDMF fields here",
    )
    p.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    _add_long_option(p)
    p.set_defaults(func=_cmd_fem)


def _add_study_parser(sub) -> None:
    """`colonna study`: a study file of any kind, with its kind's own options."""
    from .kinds import DEFAULT_KIND, KINDS, study_options

    what = (
        f"run a study file of any kind, the one its [study] kind names ({', '.join(KINDS)}; "
        f"default {DEFAULT_KIND}), into an HTML report"
    )
    p = sub.add_parser("study", help=what, description=f"{what[0].upper()}{what[1:]}.")
    p.add_argument("study", help="study file (TOML) or the name of a shipped study")
    p.add_argument(
        "--out",
        type=Path,
        required=True,
        help="write index.html, summary.json, CSV data and fields here",
    )
    p.add_argument(
        "--scheduler", help="address of a Dask distributed scheduler (default: local processes)"
    )
    p.add_argument(
        "--workers",
        type=int,
        help="local worker processes, 1 to the cores this machine has (default: the cores, "
        "at most 8)",
    )
    for name, text in study_options().items():  # a kind's own (studies/kinds.py: options)
        p.add_argument(f"--{name}", help=text)
    p.add_argument(
        "--pdf",
        action="store_true",
        help="also print the report to OUT/report.pdf (headless Chromium)",
    )
    p.add_argument(
        "--paper",
        choices=("a4", "letter"),
        help="the PDF's paper with --pdf: a4 (default) or letter",
    )
    p.add_argument(
        "--force",
        action="store_true",
        help="recompute the cases in --out saved from other inputs (another study "
        "file, record or colonna version) instead of refusing to run",
    )
    p.add_argument("--json", action="store_true", help="print summary.json")
    _add_long_option(p)
    p.set_defaults(func=_cmd_study)


def _add_tool_parsers(sub) -> None:
    """`colonna schema`, `colonna warmup` and `colonna validate`."""
    p = sub.add_parser(
        "schema",
        help="the study file's JSON Schema (keys, types, ranges, units, defaults), for editors",
    )
    p.add_argument(
        "--markdown",
        action="store_true",
        help="print the key list as Markdown tables instead (docs/study-file.md)",
    )
    p.set_defaults(func=_cmd_schema)

    p = sub.add_parser(
        "warmup",
        help="compile the kernels into numba's cache and measure the FEM's cost on this "
        "machine (make does it after installing)",
    )
    p.set_defaults(func=_cmd_warmup)

    p = sub.add_parser(
        "validate",
        help="the rigid solvers on Zhang & Makris's block (p = 2.14, alpha = 0.25): time "
        "histories, mode boundaries beside the paper's Fig. 5, overturning spectra",
    )
    p.add_argument("--out", type=Path, default=Path("out/validation"))
    p.add_argument("--json", action="store_true")
    p.set_defaults(func=_cmd_validate)


def _add_kind_commands(sub) -> None:
    """A kind's own command (studies/kinds.py, its package), one sub-command each."""
    from .kinds import KINDS

    for name, kind in KINDS.items():
        command = kind.command_module()
        if command is not None:
            p = sub.add_parser(name, help=kind.command)
            command.add_arguments(p)
            p.set_defaults(func=command.run_command)


def build_parser() -> argparse.ArgumentParser:
    parser = _Parser(prog="colonna", description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--version",
        action="version",
        version=f"colonna {importlib.import_module('colonna').__version__}",
        help="print the version of colonna (the one every report and inputs.json records)",
    )
    sub = parser.add_subparsers(dest="command", required=True)

    for add in (
        _add_rigid_parser,
        _add_spectrum_parser,
        _add_design_parser,
        _add_collar_parser,
        _add_fem_parser,
        _add_study_parser,
        _add_tool_parsers,
        _add_kind_commands,
    ):
        add(sub)
    return parser


def _raise_terminated(signum, frame):
    """SIGTERM as Ctrl-C is: an exception in the main thread, so that a command stopped by
    ``kill`` or a job scheduler ends its workers and says what it kept."""
    from .executor import StudyInterrupted

    raise StudyInterrupted(signum)


def _interrupted(args, exc: KeyboardInterrupt) -> int:
    """The one line of a command stopped by Ctrl-C or SIGTERM, and its exit status (128 +
    the signal: 130, 143). Further signals are ignored while it is said (a second Ctrl-C
    would be a traceback)."""
    if threading.current_thread() is threading.main_thread():
        signal.signal(signal.SIGINT, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
    from .executor import StudyInterrupted, saved_cases

    signum = getattr(exc, "signum", signal.SIGINT)
    message = str(exc) if isinstance(exc, StudyInterrupted) else "interrupted"
    if message == "interrupted" and args.command == "study":  # outside the cases: count them
        folder = Path(args.out) / "cases"
        message = (
            f"interrupted: {len(saved_cases(args.out))} cases saved in {folder}; "
            "run the same command again to resume"
        )
    print(f"colonna: {message}", file=sys.stderr, flush=True)
    return 128 + int(signum)


def notes_as_lines() -> None:
    """Show a :class:`colonna.core.ground.RecordNote` (a record too weak to uplift the
    column) as one ``colonna: note:`` line, once however many models read the record; other
    warnings as Python shows them. Inside ``warnings.catch_warnings()``, which undoes it."""
    from ..core.ground import RecordNote

    python_show = warnings.showwarning
    said: set[str] = set()  # each note once (each model's reading of the study gives it)

    def show(message, category, filename, lineno, file=None, line=None):
        if not issubclass(category, RecordNote):
            python_show(message, category, filename, lineno, file, line)
        elif str(message) not in said:
            said.add(str(message))
            print(f"colonna: note: {message}", file=sys.stderr, flush=True)

    warnings.simplefilter("always", RecordNote)
    warnings.showwarning = show


# The exit status of each kind of error (colonna.core.errors), the first class that matches; every
# kind ends with one line on stderr per line of its message. 130 and 143: an interrupted command.
EXIT_STATUS: tuple[tuple[type[ColonnaError], int], ...] = (
    (InputError, 2),  # bad input: a flag, a study file, a record
    (StaleResultsError, 2),  # cases in --out saved from other inputs (--force recomputes them)
    (NumericalFailure, 2),  # a run that blew up or whose energy balance failed
    (FolderInUse, 2),  # --out is being written by another colonna run
    (ColonnaError, 1),  # a study that cannot go on (executor.StudyStopped: a lost scheduler)
)


def exit_status(exc: ColonnaError) -> int:
    """The exit status of an error of colonna's (:data:`EXIT_STATUS`)."""
    return next(status for kind, status in EXIT_STATUS if isinstance(exc, kind))


def main(argv=None) -> int:
    """The command line: one line on stderr and status 2 for bad input, results in --out saved
    from other inputs, or a run whose numbers are not an answer; 1 for a study that cannot go
    on (a lost Dask scheduler); 130 (Ctrl-C) or 143 (SIGTERM) for an interrupted command, its
    worker processes ended and the cases saved kept."""
    parser = build_parser()
    args = parser.parse_args(argv)
    handlers = {}  # the handlers to put back (main is called in-process by tests too)
    if threading.current_thread() is threading.main_thread():  # where signals can be caught
        handlers = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
        signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        with warnings.catch_warnings():
            notes_as_lines()
            summary = args.func(args)
    except ColonnaError as exc:
        for line in str(exc).splitlines():  # a study file's errors: one line each
            print(f"colonna: error: {line}", file=sys.stderr)
        return exit_status(exc)
    except OSError as exc:  # an output path that cannot be made or written
        where = exc.filename if exc.filename is not None else ""
        print(f"colonna: error: cannot write {where}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    except (KeyboardInterrupt, SystemError) as exc:
        from .executor import signal_interrupt

        interrupt = signal_interrupt(exc)
        if interrupt is None:
            raise
        return _interrupted(args, interrupt)
    finally:
        for sig, handler in handlers.items():
            if handler is not None:
                signal.signal(sig, handler)
    _emit(args, summary)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
