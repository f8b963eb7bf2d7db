"""FEM study files (TOML): what to run, parsed and checked before any computation.

Every table and key, with its type, range, default and unit, is in :mod:`studies.schema`
(``colonna schema`` prints it; docs/study-file.md lists it). Here the checked file becomes a
:class:`FemStudy`: defaults that depend on the column filled in, the ground motion built (a pulse
must reach the rocking half's uplift acceleration), files found relative to the study file.
"""

from __future__ import annotations

import itertools
import math
import os
import warnings
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path

from ..core.collar import Collar
from ..core.errors import InputError, read_toml
from ..core.ground import (
    NO_MOTION,
    GroundMotion,
    HarmonicPulse,
    NoMotion,
    Record,
    RecordNote,
    cosine_pulse,
    read_record,
    sine_pulse,
    weak_record_note,
)
from ..fem.assembly import Stone
from ..fem.bed import DEFAULT as DEFAULT_BED
from ..fem.bed import Bed, bed_of
from ..fem.model import ContactSettings
from ..fem.solver import EDGE_TIME
from ..fem.toe_stress import REFINEMENTS
from ..rigid.block import Block
from . import schema
from .units import duration_text as _hours


@dataclass(frozen=True)
class FemStudy:
    """A checked FEM study: the column, its collars, the ground motion and the run's settings, SI
    units. Immutable: a variant is ``dataclasses.replace(study, initial_tilt=...)``."""

    name: str
    height: float
    width: float
    thickness: float
    cracked: bool
    stone: Stone
    collars: tuple
    ground: GroundMotion
    contact: ContactSettings
    mesh_size: float
    grading: float
    mesh_file: Path | None
    edge_length: float
    duration: float
    output_interval: float | None
    dt: float | None
    safety: float
    rigid: dict = field(default_factory=dict)
    initial_tilt: float = 0.0  # rad, theta sign
    initial_angular_velocity: float = 0.0  # rad/s
    source: str = ""
    edge_time: float = EDGE_TIME  # s
    toe_refinements: tuple = REFINEMENTS
    top_load: float = 0.0  # N, on the capital
    vertical: GroundMotion = NO_MOTION  # vertical ground motion
    replicas: int = 1  # FEM runs as an ensemble of this many replicas
    # stop a run once it can no longer overturn (fem.solver.iter_batch): for maps of outcomes
    stop_when_settled: bool = False
    bed: Bed = DEFAULT_BED  # the base's stiffness per unit area ([base])
    toe_size: float | None = None  # m: the element size at the base corners ([mesh] toe_size)

    @property
    def rocking_block(self) -> Block:
        """The rigid block that rocks: one half of a cracked column, or the whole column."""
        b = self.width / (4.0 if self.cracked else 2.0)
        mass = self.stone.density * 2.0 * b * self.height * self.thickness
        return Block(
            b=b,
            h=0.5 * self.height,
            mass=mass,
            restitution=self.rigid.get("restitution"),
            top_load=self.top_load / (2.0 if self.cracked else 1.0),
        )

    @property
    def rocking_alpha(self) -> float:
        """:func:`rocking_alpha` of this column."""
        return rocking_alpha(self.width, self.height, self.cracked, bool(self.collars))

    def to_json(self) -> dict:
        """What this study computes from, as plain JSON (what a case carries to its worker and
        what its inputs hash is of): every field but its ``name`` and ``source`` (they name it,
        they do not change a result); the ground motions by their own ``to_json``; a mesh file
        by its path and the SHA-256 of its bytes. :meth:`from_json` is the inverse."""
        data: dict = {}
        for f in fields(self):
            if f.name in IDENTITY:
                continue
            value = getattr(self, f.name)
            if f.name in ("stone", "contact", "bed"):
                value = asdict(value)
            elif f.name == "collars":
                value = [asdict(c) for c in value]
            elif f.name in ("ground", "vertical"):
                value = value.to_json()
            elif f.name == "mesh_file" and value is not None:
                value = {"path": str(value), "sha256": _file_sha256(value)}
            elif f.name == "toe_refinements":
                value = list(value)
            elif f.name == "rigid":
                value = dict(value)
            data[f.name] = value
        return data

    @classmethod
    def from_json(cls, data: dict, *, name: str = "", source: str = "") -> FemStudy:
        """The study of :meth:`to_json`, rebuilt without reading or validating a study file."""
        from ..core.ground import motion_from_json

        values = dict(data)
        values["stone"] = Stone(**values["stone"])
        values["contact"] = ContactSettings(**values["contact"])
        if "bed" in values:
            values["bed"] = Bed(**values["bed"])
        values["collars"] = tuple(Collar(**c) for c in values["collars"])
        values["ground"] = motion_from_json(values["ground"])
        values["vertical"] = motion_from_json(values["vertical"])
        if values["mesh_file"] is not None:
            values["mesh_file"] = Path(values["mesh_file"]["path"])
        values["toe_refinements"] = tuple(values["toe_refinements"])
        return cls(name=name, source=source, **values)

    @property
    def column_block(self) -> Block:
        """The whole column as one rigid block (4b wide), with the whole top load."""
        mass = self.stone.density * self.width * self.height * self.thickness
        return Block(
            b=0.5 * self.width,
            h=0.5 * self.height,
            mass=mass,
            restitution=self.rigid.get("restitution"),
            top_load=self.top_load,
        )


IDENTITY = ("name", "source")  # the fields of a FemStudy that name it (left out of its JSON)


def _file_sha256(path: Path) -> str | None:
    """The SHA-256 of a file's bytes (None where it cannot be read)."""
    import hashlib

    try:
        return hashlib.sha256(Path(path).read_bytes()).hexdigest()
    except OSError:
        return None


def case_of(study: FemStudy, **case) -> dict:
    """A case of a study kind (:func:`studies.executor.run_cases`): ``case``'s own keys, the
    study as JSON (:meth:`FemStudy.to_json`, what its inputs hash is of) and its source (which
    names it in messages and is no input). :func:`study_of_case` is the worker's side."""
    return {**case, "study": study.to_json(), "source": study.source}


def study_of_case(case: dict) -> FemStudy:
    """The study of a case made by :func:`case_of`, rebuilt without a study file."""
    return FemStudy.from_json(case["study"], source=case.get("source", ""))


def mesh_uncertainty_sizes(study: FemStudy) -> tuple[float, ...]:
    """The mesh sizes (m) of the runs that measure a FEM number's mesh-convergence uncertainty:
    2h and 4h, where the study's generated mesh leaves 4h within a rocking body's width (none
    for a mesh file)."""
    body_width = study.width / (2.0 if study.cracked else 1.0)
    if study.mesh_file is not None or 4.0 * study.mesh_size > body_width:
        return ()
    return (2.0 * study.mesh_size, 4.0 * study.mesh_size)


def toe_resolution(study: FemStudy) -> dict:
    """The toe grading rule (issue 38): the weight W (N) on the pivoting toe (the rocking
    body's, with its share of the top load), the representative tilt theta = alpha / 2 of the
    rocking body, the Winkler contact length c = sqrt(2 W / (k t theta)) on the study's bed
    (m), the toe element size c / 4 that resolves it (m) and the fine zone 2 c (m; at most half
    a body's width) over which the toe's elements keep that size
    (:func:`colonna.fem.bed.resolving_toe_size`); the Winkler peak pressure 2 W / (t c) at the
    bed's stiffness and at its range's ends (Pa), at most the yield pressure of a bed that
    yields (given with its source): the closed form's answer over the range."""
    from ..fem.bed import ELEMENTS_ACROSS, winkler_contact_length, winkler_peak_pressure

    half = study.cracked and not study.collars
    block = study.rocking_block if half else study.column_block
    weight = block.mass * block.g + (0.5 if half else 1.0) * study.top_load
    theta = 0.5 * study.rocking_alpha
    k, t, p_y = study.bed.stiffness, study.thickness, study.bed.yield_pressure
    contact = winkler_contact_length(weight, k, t, theta)
    body_width = study.width / (2.0 if study.cracked else 1.0)
    return {
        "block": "half" if half else "column",  # whose slenderness alpha is
        "weight": weight,
        "theta": theta,
        "contact_length": contact,
        "toe_size": contact / ELEMENTS_ACROSS,
        "elements_across": ELEMENTS_ACROSS,
        "zone": min(2.0 * contact, 0.5 * body_width),
        "pressure": winkler_peak_pressure(weight, k, t, theta, p_y),
        "pressure_low": winkler_peak_pressure(weight, study.bed.low, t, theta, p_y),
        "pressure_high": winkler_peak_pressure(weight, study.bed.high, t, theta, p_y),
        "yield_pressure": study.bed.yield_pressure,
        "yield_source": study.bed.yield_source or None,
    }


def toe_mesh(study: FemStudy, refinement: int):
    """The study's generated mesh (graded to ``toe_size`` at the base corners over edge_length
    where the study sets it) with its toe zones (edge_length from each base corner) refined
    ``refinement`` times. The bed's stiffness per unit area is held: the refinement
    refines the mesh only. (A mesh graded to the rule of :func:`toe_resolution` costs a step
    of about 1e-7 s on the default column: too many steps for a window; the static pivot of
    tests/test_bed.py resolves the zone.)"""
    from ..meshes.column import column_mesh

    return column_mesh(
        study.width,
        study.height,
        study.mesh_size,
        cracked=study.cracked,
        grading=study.grading,
        pinned_heights=[c.y for c in study.collars],
        toe_refinement=refinement,
        toe_zone=study.edge_length,
        toe_size=study.toe_size,
    )


def load(path) -> FemStudy:
    """The FEM study of a study file as given (no kind's defaults): for the Python API and
    ``colonna fem``; a study run by its kind is :func:`colonna.studies.study.load`."""
    path = Path(path)
    return from_dict(read_toml(path, "study file"), source=str(path), base=path.parent)


def rocking_alpha(width: float, height: float, cracked: bool, collared: bool) -> float:
    """Slenderness (rad) of the body whose impacts a rotation history shows: one half of a
    cracked column without collars, else the whole column (collars and crack friction make
    the halves rock together)."""
    if cracked and not collared:
        return math.atan2(width / 4.0, height / 2.0)
    return math.atan2(width / 2.0, height / 2.0)


def default_thickness(width: float) -> float:
    """The 2D model's out-of-plane thickness (m) when column.thickness is not given, pi w / 4:
    a half column then has the mass of a half circular column of diameter w."""
    return math.pi * width / 4.0


def from_dict(data: dict, source: str = "study", base: Path = Path(".")) -> FemStudy:
    """The study of a parsed TOML file: checked against :mod:`studies.schema`, then built
    (:func:`from_spec`)."""
    return from_spec(schema.parse(data, source), source, base)


def from_spec(spec: schema.StudyFile, source: str = "study", base: Path = Path(".")) -> FemStudy:
    """The study of a validated study file (:func:`studies.schema.parse`): the defaults that
    depend on the column filled in, the ground motions built (records read relative to
    ``base``). Validates nothing again."""
    column = column_of(spec, source, base)
    ground = _ground(spec.ground, column.rocking_block, base, source)
    vertical = _vertical(spec.ground, ground, base, source)
    end = max(ground.end_time, vertical.end_time)
    study = replace(
        column, ground=ground, vertical=vertical, duration=spec.run.duration or end + 1.5
    )
    if (
        not study.ground.moves
        and study.initial_tilt == 0.0
        and study.initial_angular_velocity == 0.0
    ):
        raise InputError(
            f"{source}: ground.pulse = 'none' needs run.initial_tilt or "
            "run.initial_angular_velocity (else the column stays at rest)"
        )
    return study


def column_of(spec: schema.StudyFile, source: str = "study", base: Path = Path(".")) -> FemStudy:
    """The column of a validated study file without its ground motion (no motion, the file's
    run.duration or 0): its collars, mesh and run settings with the defaults that depend on
    the column filled in (thickness pi w / 4, mesh size w / 16, toe length a tenth of a body's
    width). What the model and its stable step are built from, for every kind, also one whose
    cases set their own motion."""
    column = spec.column
    if column is None:
        raise InputError(f"{source}: column.height is required for a FEM study")
    mesh = spec.mesh
    body_width = column.width / (2.0 if column.cracked else 1.0)
    mesh_file = None
    if mesh.file is not None:
        mesh_file = (base / mesh.file).resolve()
        if not mesh_file.is_file():
            raise InputError(f"{source}: mesh.file = {mesh.file!r}: no such file")
    return FemStudy(
        name=spec.study.name or Path(source).stem,
        height=column.height,
        width=column.width,
        thickness=column.thickness or default_thickness(column.width),
        cracked=column.cracked,
        stone=Stone(**spec.stone.model_dump()),
        collars=tuple(Collar(**c.model_dump()) for c in spec.collar),
        ground=NoMotion(),
        contact=ContactSettings(**spec.contact.model_dump()),
        bed=bed_of(
            spec.base.bed,
            spec.base.stiffness,
            *(spec.base.stiffness_range or (None, None)),
            plastic=spec.base.plastic,
            yield_pressure=spec.base.yield_pressure,
        ),
        mesh_size=mesh.size or column.width / 16.0,
        grading=mesh.grading,
        mesh_file=mesh_file,
        edge_length=mesh.edge_length or 0.1 * body_width,
        duration=spec.run.duration or 0.0,
        output_interval=spec.run.output_interval,
        dt=spec.run.dt,
        safety=spec.run.safety,
        rigid=spec.rigid.model_dump(exclude_none=True),
        source=source,
        edge_time=mesh.edge_time,
        toe_size=mesh.toe_size,
        toe_refinements=tuple(mesh.toe_refinements),
        top_load=column.top_load,
        initial_tilt=spec.run.initial_tilt,
        initial_angular_velocity=spec.run.initial_angular_velocity,
        replicas=spec.run.replicas,
    )


def model_record(study: FemStudy) -> dict:
    """The FEM model of a study's own mesh as its runs build it (:func:`build`), for the
    inputs on record: nodes, elements and degrees of freedom; the stable time step
    (:func:`colonna.fem.model.stable_time_step`: safety x 2 / omega_max x the contact damping's
    reduction) and the step used (run.dt where given, else the stable one); the row spacing
    of the histories (a whole number of steps nearest the output interval: duration / 400
    by default); the base contact's stiffness per node (N/m: the bed's k x t x tributary
    length, [base]) and the bed's k (N/m^3), its range and source. Variants of the study
    (a finer mesh, a toe refinement) build their own."""
    import numpy as np

    from ..fem.model import stable_time_step

    model = build(study)
    step = stable_time_step(model, study.safety)
    dt = study.dt if study.dt is not None else step.dt
    record = {
        "nodes": int(model.mesh.n_nodes),
        "elements": int(model.mesh.cells.shape[1]),
        "dofs": int(model.n_dofs),
        "dt_stable": step.dt,
        "dt_critical": step.critical,
        "dt_critical_stone": step.critical_elastic,
        "dt": dt,
        "penalty_base_mean": float(np.mean(model.base_kn)),
        "penalty_base_min": float(np.min(model.base_kn)),
        "penalty_base_max": float(np.max(model.base_kn)),
        "bed_stiffness": study.bed.stiffness,
        "bed_stiffness_low": study.bed.low,
        "bed_stiffness_high": study.bed.high,
        "bed_source": study.bed.source,
    }
    interval = study.output_interval or (study.duration / 400.0 if study.duration else None)
    if interval is not None:
        per_output = max(1, int(round(interval / dt)))
        record.update(steps_per_output=per_output, output_interval_used=per_output * dt)
    return record


def _vertical(ground: schema.Ground, horizontal, base: Path, source: str = "study"):
    """The vertical ground motion of [ground] vertical_* (NO_MOTION without one). Its peak must be
    below g: at g the ground falls away from the column (the harmonic's amplitude is checked by
    the schema)."""
    if ground.vertical_record is not None:
        scale = 1.0 if ground.vertical_scale is None else ground.vertical_scale
        record = _read_study_record(
            base, ground.vertical_record, "ground.vertical_record", source, schema.G
        )
        peak = abs(scale) * record.peak_acceleration
        if peak >= schema.G:
            raise InputError(
                f"{source}: ground.vertical_record {ground.vertical_record!r} peaks at "
                f"{record.peak_acceleration:g} m/s^2, times ground.vertical_scale = {scale:g} "
                f"that is {peak:g} m/s^2, which lifts the column off the ground: it must be "
                f"below g = {schema.G:g} m/s^2"
            )
        return record.scaled(scale)
    if ground.vertical_amplitude is None:
        return NO_MOTION
    period = ground.vertical_period
    assert period is not None  # the schema asks for it with vertical_amplitude
    duration = ground.vertical_duration or (
        horizontal.end_time if horizontal.end_time > 0.0 else period
    )
    return HarmonicPulse(
        "sine",
        ground.vertical_amplitude,
        2.0 * math.pi / period,
        ground.vertical_phase or 0.0,
        duration,
    )


def _read_study_record(base: Path, given: str, key: str, source: str, g: float):
    """A study's record file, read by :func:`read_record`; what is wrong with it is said with
    the study's key that names it (``ground.record = 'x.AT2': record file ... cannot be
    read``)."""
    try:
        record = read_record(base / given, g=g)
    except InputError as exc:
        raise InputError(f"{source}: {key} = {given!r}: {exc}") from None
    start, end = float(record.time[0]), float(record.time[-1])
    if end > schema.LONGEST:  # a clock time or an offset, not a record's own time axis
        raise InputError(
            f"{source}: {key} = {given!r}: the record runs from t = {start:g} s to {end:g} s, "
            f"past the longest motion a study runs ({schema.LONGEST:g} s): its times must "
            "start near 0 (shift them by the first time)"
        )
    return record


def played_record(ground: schema.Ground, base: Path, source: str, g: float) -> Record:
    """The study's horizontal record as read (:func:`_read_study_record`) and played at its
    ground.time_scale (t -> t / time_scale: faster), before its factor."""
    assert ground.record is not None  # the schema asks for it with pulse = "record"
    record = _read_study_record(base, ground.record, "ground.record", source, g)
    speed = ground.time_scale or 1.0
    if speed != 1.0:
        record = Record(record.time / speed, record.acceleration_values, record.name)
    return record


def record_scale(ground: schema.Ground, record: Record) -> tuple[float, str]:
    """The factor on a record (as read, played at its time_scale) and how it was set: ground.scale
    (default 1), or scale_to_pga over its PGA, or scale_to_pgv over its PGV (those of the
    motion as the solvers apply it, as the fragility's: :func:`colonna.core.intensity.
    peak_ground`)."""
    from ..core.intensity import peak_ground

    for measure, unit in (("pga", "m/s^2"), ("pgv", "m/s")):
        target = getattr(ground, f"scale_to_{measure}")
        if target is None:
            continue
        peak = peak_ground(record, measure)
        if peak == 0.0:
            raise InputError(f"ground.scale_to_{measure}: the record {ground.record!r} never moves")
        return (
            target / peak,
            f"scale_to_{measure} {target:g} {unit} / the record's {measure.upper()} "
            f"{peak:.6g} {unit}",
        )
    return (1.0 if ground.scale is None else ground.scale), "1 (the record as read)"


def _ground(ground: schema.Ground, block: Block, base: Path, source: str = "study"):
    """The horizontal ground motion; a pulse must reach the rocking half's uplift. A record
    that does not is a :class:`RecordNote` warning (its file is read by
    :func:`read_record`: uniform sampling, MAX_RECORD_STEP or finer, AT2 units from its
    header)."""
    if ground.pulse == "none":
        return NoMotion()
    uplift = block.uplift_acceleration("nonlinear")
    if ground.pulse == "record":
        assert ground.record is not None  # the schema asks for it with pulse = "record"
        record = played_record(ground, base, source, block.g)
        scale, _ = record_scale(ground, record)
        record = record.scaled(scale)
        if ground.vertical_record is None and ground.vertical_amplitude is None:
            # a vertical motion lowers the uplift acceleration: then the record may rock it
            note = weak_record_note(
                record,
                uplift,
                what=f"{source}: ground.record {ground.record!r}",
                scale=scale,
                scale_name="ground.scale",
                uplift_text="g tan(alpha) (1 + lambda) of the rocking half",
                in_m_s2=Path(ground.record).suffix.lower() != ".at2",
                g=block.g,
            )
            if note is not None:
                warnings.warn(note, RecordNote, stacklevel=3)
        return record
    amplitude = (
        ground.amplitude if ground.amplitude is not None else ground.amplitude_ratio * uplift
    )
    omega = (
        2.0 * math.pi / ground.period if ground.period is not None else ground.omega_ratio * block.p
    )
    if abs(amplitude) < uplift:
        raise InputError(
            f"{source}: ground.amplitude = {amplitude:g} m/s^2 is below the "
            f"uplift acceleration g tan(alpha) (1 + lambda) = {uplift:g} m/s^2 "
            "of the rocking half"
        )
    make = sine_pulse if ground.pulse == "sine" else cosine_pulse
    return make(amplitude, omega, uplift)


def build(study: FemStudy):
    """Mesh and model of the study."""
    from ..fem.model import build_model

    if study.mesh_file is not None:
        from ..meshes.io import read

        mesh = read(study.mesh_file)
        for name, value, expected in (
            ("width", mesh.width, study.width),
            ("height", mesh.height, study.height),
        ):
            if abs(value - expected) > 1e-6 * expected:
                raise InputError(
                    f"mesh.file {study.mesh_file.name}: its {name} {value:g} m "
                    f"differs from column.{name} = {expected:g} m"
                )
        if mesh.cracked != study.cracked:
            raise InputError(
                f"mesh.file {study.mesh_file.name} has {mesh.n_bodies} bodies but "
                f"column.cracked = {str(study.cracked).lower()}"
            )
    else:
        mesh = toe_mesh(study, 1)
    return build_model(
        mesh,
        study.stone,
        study.thickness,
        study.collars,
        study.contact,
        top_load=study.top_load,
        bed=study.bed,
    )


def run_fem(
    study: FemStudy,
    *,
    replicas: int | None = None,
    out_dir=None,
    progress: bool = False,
    checkpoint=None,
):
    """The FEM run of a study as an ensemble of ``replicas`` (default ``study.replicas``) runs
    perturbed at round-off level (:func:`colonna.fem.solver.run_ensemble`); replica 0 is the
    unperturbed run and writes the files of a run into ``out_dir``.

    Every FEM run of every study kind goes through here (the single study, the cross-check,
    free rocking, the sweeps; the spectrum's grid points through :func:`iter_fem`, batched on
    one model): a variant is a changed study
    (``dataclasses.replace``), never another argument set. The refinement of the toe stress
    restarts these runs on finer meshes (:func:`colonna.fem.toe_stress.toe_stress_refinement`).
    ``checkpoint`` (:class:`colonna.fem.checkpoint.Checkpoint`): where the ensemble saves its
    state as it goes, and goes on from when run again (a study's FEM case:
    :func:`case_checkpoint`)."""
    from ..fem.solver import run_ensemble

    model = build(study)
    return run_ensemble(
        model,
        study.ground,
        study.duration,
        study.replicas if replicas is None else replicas,
        out_dir=out_dir,
        vertical=study.vertical,
        progress=progress,
        checkpoint=checkpoint,
        **_run_settings(study),
    )


def case_checkpoint(case: dict, directory):
    """The checkpoint of a study's FEM case in its folder (``directory``/checkpoint), keyed by
    the hash of the case's inputs (:func:`studies.executor.case_inputs`: the case, the bytes of
    the files it reads, the colonna version): a case computed again from other inputs never
    goes on from it."""
    from ..fem.checkpoint import Checkpoint
    from .executor import case_inputs, inputs_hash

    return Checkpoint(Path(directory) / "checkpoint", inputs_hash(case_inputs(case)))


def run_multibody(study: FemStudy, dt: float | None = None, touching_dt: float | None = None):
    """The rigid multibody model of a study (:func:`colonna.rigid.multibody.rock_multibody`; its
    default step where ``dt`` is None; ``touching_dt`` as rock_multibody's). Every study kind's
    multibody run goes through here (the cross-check, the design study, the spectrum's grid
    points, free rocking): a variant is a changed study (``dataclasses.replace``), as for
    :func:`run_fem`."""
    from ..rigid.multibody import rock_multibody

    return rock_multibody(
        study.rocking_block,
        study.ground,
        study.collars,
        cracked=study.cracked,
        friction=study.contact.friction,
        duration=study.duration,
        vertical=study.vertical,
        initial_tilt=study.initial_tilt,
        initial_angular_velocity=study.initial_angular_velocity,
        dt=dt,
        touching_dt=touching_dt,
    )


def run_sdof(study: FemStudy, *, whole_column: bool = False):
    """The SDOF rocking block of a study, nonlinear (:func:`colonna.rigid.solve.rock`): the
    half (or the whole, if not cracked) with the study's collars, the paper's model; with
    ``whole_column`` the uncracked column without collars (the monolith). Every study kind's
    SDOF run goes through here, as for :func:`run_fem`."""
    from ..rigid.solve import rock

    if whole_column:
        block, collars = study.column_block, ()
    else:
        block, collars = study.rocking_block, study.collars
    return rock(
        block,
        study.ground,
        collars,
        model="nonlinear",
        duration=study.duration,
        vertical=study.vertical,
        initial_tilt=study.initial_tilt,
        initial_angular_velocity=study.initial_angular_velocity,
    )


def _run_settings(study: FemStudy) -> dict:
    """The solver's run settings of a study (those of :data:`SHARED_BY_A_BATCH` that are not
    the model's): one place for run_fem and iter_fem."""
    return {
        "dt": study.dt,
        "safety": study.safety,
        "output_interval": study.output_interval,
        "edge_length": study.edge_length,
        "edge_time": study.edge_time,
        "initial_tilt": study.initial_tilt,
        "initial_angular_velocity": study.initial_angular_velocity,
        "stop_when_settled": study.stop_when_settled,
    }


# the keys of a FemStudy that make its model and time step (build, stable_time_step)
MODEL_KEYS = (
    "height",
    "width",
    "thickness",
    "cracked",
    "stone",
    "collars",
    "contact",
    "bed",
    "mesh_size",
    "toe_size",
    "grading",
    "mesh_file",
    "top_load",
    "safety",
    "dt",
)


# what the runs of iter_fem may not differ in: the model and the run settings (they share one
# model and one stable step); the ground motions and durations may differ
SHARED_BY_A_BATCH = MODEL_KEYS + (
    "edge_length",
    "output_interval",
    "initial_tilt",
    "initial_angular_velocity",
    "edge_time",
    "stop_when_settled",
)


def iter_fem(studies: list[FemStudy], *, slots: int | None = None, **options):
    """One FEM run of each study (no replicas). The studies that differ only in their ground
    motion and duration (the pulses of a grid: :data:`SHARED_BY_A_BATCH` equal) share a model
    and advance together on the batched kernel (:func:`colonna.fem.solver.iter_batch`,
    ``slots`` runs at a time, default :data:`colonna.fem.solver.BATCH_SLOTS`). Yields (index in
    studies, FemResult) as each run ends; each is the same bits as ``run_fem(study,
    replicas=1)``, a run whose energy balance fails rerun at half the step up to
    :data:`colonna.fem.solver.STEP_HALVINGS` times as there (the failed runs of a batch
    together). ``options``: more of iter_batch's (its ``stop_in_weak_tail``)."""
    from ..fem.solver import (
        BATCH_SLOTS,
        STEP_HALVINGS,
        _with_halvings,
        iter_batch,
        unreliable_reason,
    )

    notes: dict[int, str] = {}  # why a run was rerun at a halved step (unreliable_reason)
    groups: list[list[int]] = []
    for index, study in enumerate(studies):
        for members in groups:
            first = studies[members[0]]
            if all(getattr(study, k) == getattr(first, k) for k in SHARED_BY_A_BATCH):
                members.append(index)
                break
        else:
            groups.append([index])
    for members in groups:
        # the longest runs first: they advance together, and the short ones take the slots that
        # runs ending early leave, so the batch does not end on a few long runs alone
        members.sort(key=lambda i: -studies[i].duration)
        first = studies[members[0]]
        model = build(first)
        settings = {**_run_settings(first), **options}
        halvings = 0
        while members:
            runs = iter_batch(
                model,
                [studies[i].ground for i in members],
                [studies[i].duration for i in members],
                verticals=[studies[i].vertical for i in members],
                slots=BATCH_SLOTS if slots is None else slots,
                progress=False,
                **settings,
            )
            failed: list[tuple[int, float]] = []  # (index in studies, its step)
            for k, result in runs:
                reason = unreliable_reason([result.summary])
                if halvings:
                    result = _with_halvings(result, halvings, notes[members[k]])
                if reason is None or halvings == STEP_HALVINGS:
                    yield members[k], result
                else:  # as run_ensemble: rerun at half the step (those that failed, together)
                    notes[members[k]] = reason
                    failed.append((members[k], result.summary["dt"]))
            members = [i for i, _ in failed]
            if failed:
                halvings += 1
                settings["dt"] = 0.5 * failed[0][1]


# --- the work of FEM runs, bounded before they run ------------------------------------------------

# CPU seconds to advance one node of a mesh by one explicit time step, for one state (a replica
# or a grid point), on the machine of the README's timings, in a batch (the work limit's unit:
# the estimates of time use this machine's calibrated cost model, studies.cost)
NODE_STEP_SECONDS = 25e-9
WORK_LIMIT_SECONDS = 2 * 3600.0  # the CPU time a study (or colonna fem) may ask for, unless --long
# what one state keeps per output row (measured: 54.5 kB on 1,512 nodes): its displacement and
# velocity frames, 4 numbers a node, and the row's numbers and contact state
OUTPUT_BYTES_PER_NODE = 32
OUTPUT_ROW_BYTES = 8000
STATE_BYTES_PER_NODE = 400  # a state's own arrays in the kernel (positions, velocities, forces)


@dataclass(frozen=True)
class FemRun:
    """``states`` FEM runs of one model advanced together: its ``nodes``, ``steps`` and
    ``outputs`` (rows), the ``case`` they are part of (a label: the runs of one case run one
    after the other, cases side by side) and its ``stage`` (the stages of a study run one after
    the other). A case without FEM runs (a rigid model's) is a FemRun of no states and its
    ``other_seconds``."""

    nodes: int
    steps: float
    outputs: float
    states: int
    case: str
    stage: int = 0
    other_seconds: float = 0.0  # CPU seconds of the case's work outside the FEM (rigid models)

    @property
    def seconds(self) -> float:
        """CPU seconds on this machine (:func:`studies.cost.cost_model`)."""
        from .cost import cost_model

        fem = cost_model().run_seconds(self.nodes, self.steps, self.outputs, self.states)
        return fem + self.other_seconds


@dataclass(frozen=True)
class FemWork:
    """What FEM runs ask for, estimated before they run: ``state_steps`` (time steps x states,
    a state being a replica or a grid point), ``node_steps`` (each state-step x the nodes of its
    mesh), the largest mesh's ``nodes``, ``memory`` (bytes) of the largest run, its states
    held at once, and the ``runs`` themselves (:class:`FemRun`) for their time. Runs add up
    (``+``)."""

    state_steps: float = 0.0
    node_steps: float = 0.0
    nodes: int = 0
    memory: float = 0.0
    runs: tuple[FemRun, ...] = ()

    @property
    def seconds(self) -> float:
        """CPU seconds at :data:`NODE_STEP_SECONDS` a node-step (the work limit's measure)."""
        return self.node_steps * NODE_STEP_SECONDS

    @property
    def cpu_seconds(self) -> float:
        """CPU seconds of the runs on this machine (its calibrated cost model)."""
        return sum(run.seconds for run in self.runs)

    def wall_seconds(self, workers: int) -> float:
        """Wall seconds of the runs on ``workers`` cores: per stage, its cases dealt as the
        executor deals them (the costliest first, each to the least loaded worker), the
        stages one after the other."""
        total = 0.0
        for stage in sorted({run.stage for run in self.runs}):
            cases: dict[str, float] = {}
            for run in self.runs:
                if run.stage == stage:
                    cases[run.case] = cases.get(run.case, 0.0) + run.seconds
            load = [0.0] * max(1, workers)
            for seconds in sorted(cases.values(), reverse=True):
                load[load.index(min(load))] += seconds
            total += max(load)
        return total

    def __add__(self, other: FemWork) -> FemWork:
        return FemWork(
            self.state_steps + other.state_steps,
            self.node_steps + other.node_steps,
            max(self.nodes, other.nodes),
            max(self.memory, other.memory),
            self.runs + other.runs,
        )


def fem_work(
    study: FemStudy,
    states: int = 1,
    *,
    held: int | None = None,
    models: dict | None = None,
    case: str | None = None,
    stage: int = 0,
    until: float | None = None,
) -> FemWork:
    """The work of ``states`` FEM runs of ``study`` over its whole duration (its replicas, or
    grid points that share its model and duration; ``held`` of them at once, default all), as
    :func:`run_fem` would run them: the model is built for its nodes and stable step (once per
    model in ``models``, a cache shared by the runs of a study: about 0.1 s for the default
    column). ``case``: the case they are part of (default: a case of their own), ``stage``
    the study's stage (:class:`FemRun`). A run that stops early (overturned, settled) costs
    less: ``until`` (s), where the runs are expected to stop, bounds the time they are
    estimated to take (not their memory, which is bounded for the whole duration)."""
    key = tuple(getattr(study, k) for k in MODEL_KEYS)
    if models is None or key not in models:
        from ..fem.model import stable_time_step

        model = build(study)
        dt = study.dt if study.dt is not None else stable_time_step(model, study.safety).dt
        found = (model.n_dofs // 2, dt)
        if models is not None:
            models[key] = found
    else:
        found = models[key]
    nodes, dt = found
    interval = study.output_interval or study.duration / 400.0
    per_output = max(1.0, round(interval / dt))
    outputs = math.ceil(study.duration / (per_output * dt))
    steps = float(outputs) * per_output
    per_state = (
        outputs * (OUTPUT_BYTES_PER_NODE * nodes + OUTPUT_ROW_BYTES)
        + STATE_BYTES_PER_NODE * nodes
        + 16.0 * per_output  # the ground accelerations of an output interval
        + 32.0 * max(1.0, round(study.edge_time / dt))  # the toe stresses' averaging window
    )
    at_once = states if held is None else min(states, held)
    share = 1.0 if until is None else min(1.0, max(0.0, until) / study.duration)
    run = FemRun(
        nodes,
        steps * share,
        outputs * share,
        states,
        case if case is not None else f"run-{next(_RUN_LABELS)}",
        stage,
    )
    return FemWork(steps * states, steps * states * nodes, nodes, at_once * per_state, (run,))


_RUN_LABELS = itertools.count()


def memory_limit() -> float:
    """The memory (bytes) one FEM run may ask for: half this machine's (16 GiB where it cannot
    be read)."""
    try:
        return 0.5 * os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
    except (AttributeError, ValueError, OSError):
        return 16.0 * 2**30


def require_bounded_work(
    work: FemWork, *, long: bool = False, what: str = "this study", fewer: str = ""
) -> None:
    """An InputError of one line where ``work`` is more than :data:`WORK_LIMIT_SECONDS` of CPU
    (unless ``long``: the user asked for it) or more memory than :func:`memory_limit` (always:
    it would not fit), giving the estimate and what to change (``fewer``: the study's own ways
    to ask for less, "fewer replicas")."""
    if work.seconds > WORK_LIMIT_SECONDS and not long:
        raise InputError(
            f"{what} asks for {work.state_steps:.2g} state-steps (time steps x runs and "
            f"replicas) on up to {work.nodes:,} nodes, about {_hours(work.seconds)} of CPU at "
            f"{NODE_STEP_SECONDS * 1e9:g} ns a node-step (limit {_hours(WORK_LIMIT_SECONDS)}): "
            f"shorten [run] duration, coarsen [mesh] size{fewer}, or pass --long to run it "
            "anyway"
        )
    limit = memory_limit()
    if work.memory > limit:
        raise InputError(
            f"{what} asks for about {work.memory / 2**30:.3g} GiB of memory for one FEM run's "
            f"history and states (at most {limit / 2**30:.3g} GiB, half of this machine's): "
            "lengthen [run] output_interval, shorten [run] duration or coarsen [mesh] size"
        )
