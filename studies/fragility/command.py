"""``colonna fragility``: the fragility of the SDOF alone, fast, from a fragility study file or
from flags (a block, its collars, a suite and a ladder), printing the fits.

The SDOF runs are the study's (:func:`.models.sdof_runs`), in this process and without the
executor, the report or the other models; the fits are the study's too
(:func:`.runner.limit_state_fits`). ``--out`` writes ``fragility.json``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from ...core.errors import InputError

HELP = "fragility of the SDOF alone over a record suite (IDA or stripes), fast: the fits"
SHIPPED = Path(__file__).resolve().parents[1]  # the shipped study files


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The command's options (the block and collar options are ``colonna rigid``'s)."""
    from ..options import add_block_options, add_collar_option
    from .schema import INTENSITY_MEASURES

    parser.add_argument(
        "study",
        nargs="?",
        help="a fragility study file, or the name of a shipped one: its column, suite and "
        "[fragility] table (or give --suite, the block and --ladder or --levels)",
    )
    add_block_options(parser)
    add_collar_option(parser)
    g = parser.add_argument_group("suite and intensity levels (without a study file)")
    g.add_argument("--suite", type=Path, help="a folder of records or a TOML list of them")
    g.add_argument(
        "--intensity", choices=tuple(INTENSITY_MEASURES), default="pga_rocking", help="the IM"
    )
    g.add_argument("--period", type=float, help="period of Sa (s), with --intensity sa")
    g.add_argument("--ladder", help="START:STOP:N intensity levels (IDA)")
    g.add_argument("--levels", help="comma-separated intensity levels (stripes, MSA)")
    g.add_argument("--design", type=float, help="design intensity (the IM's unit)")
    g.add_argument("--theta-ratio", type=float, default=0.5, help="|theta|/alpha threshold")
    g.add_argument("--bootstrap", type=int, default=200, help="bootstrap resamples")
    g.add_argument("--seed", type=int, default=0, help="bootstrap seed")
    g.add_argument("--rtol", type=float, help="relative tolerance of the SDOF runs")
    parser.add_argument("--out", type=Path, help="write fragility.json here")
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def _table_from_flags(args) -> dict:
    """The [fragility] table the flags describe (validated as a study file's)."""
    if args.suite is None:
        raise InputError("give a fragility study file, or --suite with the block and levels")
    table: dict = {
        "suite": str(args.suite),
        "intensity": args.intensity,
        "theta_ratio": args.theta_ratio,
        "bootstrap": args.bootstrap,
        "seed": args.seed,
    }
    if args.period is not None:
        table["period"] = args.period
    if args.rtol is not None:
        table["sdof_rtol"] = args.rtol
    if args.ladder is not None and args.levels is not None:
        raise InputError("give --ladder (IDA) or --levels (stripes), not both")
    if args.ladder is not None:
        from ...rigid.spectrum import parse_range

        ladder = parse_range(args.ladder, "--ladder")
        table.update(
            analysis="ida", ladder=[float(ladder[0]), float(ladder[-1])], steps=int(ladder.size)
        )
    elif args.levels is not None:
        try:
            levels = [float(x) for x in args.levels.split(",")]
        except ValueError:
            raise InputError(f"--levels = {args.levels!r} is not a comma-separated list") from None
        table.update(analysis="msa", levels=levels)
    else:
        raise InputError("give --ladder START:STOP:N (IDA) or --levels L1,L2,... (stripes)")
    if args.design is None:
        raise InputError("give --design, the design intensity (in the IM's unit)")
    table["design_intensity"] = args.design
    return table


def _inputs_from_study(args) -> tuple:
    """(spec, block, collars, records, levels, record names, intensity) from a study file."""
    from ..study import load
    from .runner import setup

    given = [f"--{k}" for k in ("suite", "ladder", "levels", "design") if getattr(args, k)]
    if given:
        raise InputError(f"{', '.join(given)}: the study file gives them")
    path = Path(args.study)
    if not path.exists() and (SHIPPED / f"{args.study}.toml").exists():
        path = SHIPPED / f"{args.study}.toml"
    s = setup(load(path))
    spec, block, collars = s.spec, s.column.rocking_block, s.column.collars
    records, levels = s.records, s.levels
    names = [entry.name for entry in s.suite]
    intensity = s.intensity
    return spec, block, collars, records, levels, names, intensity


def _inputs_from_flags(args) -> tuple:
    """(spec, block, collars, records, levels, record names, intensity) from the flags:
    the [fragility] table they make, the block, its collars and the suite's intensities."""
    from ...core.intensity import intensity_measures
    from ...core.suite import load_suite
    from .. import schema
    from ..options import block_from_args, collars_from_args
    from . import analysis
    from .runner import intensity_of

    try:
        spec = schema.parse_table("fragility", _table_from_flags(args), "flags")
    except InputError as exc:
        raise InputError(_as_flags(str(exc))) from None
    block, collars = block_from_args(args), collars_from_args(args)
    suite = load_suite(spec.suite, g=block.g)
    records = tuple(entry.scaled for entry in suite)
    names = [entry.name for entry in suite]
    periods = [spec.period] if spec.intensity == "sa" else []
    intensity = np.array(
        [
            intensity_of(
                intensity_measures(r, periods=periods, block=block), spec.intensity, spec.period
            )
            for r in records
        ]
    )
    if spec.analysis == "ida":
        assert spec.ladder is not None
        levels = analysis.ladder(spec.ladder[0], spec.ladder[1], spec.steps)
    else:
        levels = np.array(spec.levels, dtype=float)
    return spec, block, collars, records, levels, names, intensity


def _print_fits(spec, summary: dict, collars, levels) -> None:
    """The fits of :func:`run_command` as a table, one line a limit state."""
    from . import analysis
    from .runner import answer_fit
    from .schema import INTENSITY_MEASURES

    records, seconds = summary["records"], summary["seconds"]
    fits, law = summary["limit_states"], summary["collars"]
    unit = INTENSITY_MEASURES[spec.intensity]
    unit = "" if unit == "-" else f" {unit}"
    print(
        f"SDOF, {len(records)} records x {levels.size} levels of {spec.intensity}{unit} "
        f"({summary['runs']} runs in {seconds:.2f} s); P at the design intensity "
        f"{spec.design_intensity:g}{unit}, medians in{unit or ' ' + spec.intensity}, "
        f"{100 * spec.confidence:.0f} % bootstrap intervals:"
    )
    state_names = {
        name: f"|theta| / alpha > {spec.theta_ratio:g}" if name == "rotation" else text
        for name, text in analysis.LIMIT_STATES.items()
    }
    if collars:
        past = law["past_fy"]
        print(
            f"collars: {law['words']}"
            + (
                f"; in {past['runs']} of the {past['of']} runs it survived their stress passed "
                f"f_y, up to {past['largest_utilisation']:.3g} f_y: its survival there rests "
                "on collars past their strength"
                if past
                else ""
            )
        )
    print(f"{'limit state':24s} {'P(design)':>22s} {'median':>22s} {'beta':>20s}  fit")
    for name, entry in fits.items():
        best = answer_fit(entry)
        if best is None:
            print(f"{state_names[name]:24s} {entry.get('why', 'no curve')}")
            continue
        f, (pl, ph) = best["fit"], best["probability_interval"]
        (ml, mh), (bl, bh) = best["median_interval"], best["beta_interval"]
        print(
            f"{state_names[name]:24s} {best['probability']:8.3g} [{pl:.3g}, {ph:.3g}]".ljust(48)
            + f"{f['median']:8.4g} [{ml:.3g}, {mh:.3g}]".rjust(22)
            + f"{f['beta']:7.3g} [{bl:.3g}, {bh:.3g}]".rjust(21)
            + f"  {f['method']}"
            + (
                " (a step: the data separate, the median is the geometric mean of the two "
                "levels it lies between)"
                if f["separated"]
                else ""
            )
            + "".join(f"; extrapolated: {w}" for w in best.get("extrapolated", ()))
        )
    for name, why in summary["unreachable"].items():
        print(f"{state_names[name]:24s} cannot be reached by this model ({why})")


def run_command(args) -> dict | None:
    """Run the SDOF over the suite and print (or return, with --json) the fits."""
    from . import analysis
    from .models import collar_law, sdof_runs, unreachable
    from .runner import limit_state_fits

    inputs = _inputs_from_study(args) if args.study is not None else _inputs_from_flags(args)
    spec, block, collars, records, levels, names, intensity = inputs
    study = _Sdof(block, collars)
    start = time.perf_counter()
    runs = [
        sdof_runs(study, r, analysis.scales_for(levels, im, name), rtol=spec.sdof_rtol)
        for r, im, name in zip(records, intensity, names)
    ]
    seconds = time.perf_counter() - start
    fits = limit_state_fits(analysis.exceedances(runs, spec.theta_ratio), levels, spec)
    law = collar_law(study, "sdof")
    law["past_fy"] = analysis.past_yield(runs) if collars else None
    summary = {
        "intensity": spec.intensity,
        "design_intensity": spec.design_intensity,
        "levels": levels.tolist(),
        "records": names,
        "runs": len(records) * levels.size,
        "seconds": seconds,
        "limit_states": fits,
        "collars": law,
        "unreachable": unreachable(study, "sdof"),
    }
    if args.out is not None:
        from ..output import write_json

        write_json(Path(args.out) / "fragility.json", summary)
    if args.json:
        return summary
    _print_fits(spec, summary, collars, levels)
    return None


FLAGS = {
    "fragility.design_intensity": "--design",
    "fragility.ladder": "--ladder",
    "fragility.steps": "--ladder",
    "fragility.levels": "--levels",
    "fragility.theta_ratio": "--theta-ratio",
    "fragility.bootstrap": "--bootstrap",
    "fragility.sdof_rtol": "--rtol",
    "fragility.period": "--period",
}


def _as_flags(message: str) -> str:
    """A [fragility] table's error with each key named as the flag that set it."""
    for key, flag in FLAGS.items():
        message = message.replace(key, flag)
    return message


class _Sdof:
    """What :func:`.models.sdof_runs` reads of a study: the rocking block and its collars."""

    def __init__(self, block, collars):
        self.rocking_block, self.collars = block, tuple(collars)
