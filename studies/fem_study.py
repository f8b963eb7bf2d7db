"""The FEM study: a study's column, its collars, its ground motion and its run settings.

A study file is read once, by :func:`studies.study.load` (the one ``load``), into a
:class:`studies.study.Study`; the column it describes is :attr:`Study.fem
<studies.study.Study.fem>`, a :class:`FemStudy` built here from the validated file
(:func:`from_spec`; :func:`from_dict` validates a parsed file first): defaults that depend on
the column filled in, the ground motion built (a pulse must reach the rocking half's uplift
acceleration), files found relative to the study file. Every table and key, with its type,
range, default and unit, is in :mod:`studies.schema`. The models of a FemStudy are built and
run in :mod:`studies.models`; the work of its FEM runs is bounded in :mod:`studies.work`.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import asdict, dataclass, field, fields, replace
from pathlib import Path

from ..core.collar import Collar
from ..core.errors import InputError
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
    # (from, to) m: where the crack runs in the FEM ([column] crack; None: the full height)
    crack: tuple | None = None
    # the fraction of the thickness the crack runs through ([column] crack_depth; 1: through)
    crack_depth: float = 1.0

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
            if f.name == "crack_depth" and self.crack_depth == 1.0:
                continue  # a through crack: the JSON (and inputs hash) of before the key
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
        if values.get("crack") is not None:
            values["crack"] = tuple(values["crack"])
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
        stone=Stone(**spec.stone.model_dump(exclude={"preset"})),
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
        crack=None if column.crack is None else tuple(column.crack),
        crack_depth=column.crack_depth,
    )


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
