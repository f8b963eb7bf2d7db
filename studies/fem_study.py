"""FEM study files (TOML): what to run, parsed and checked before any computation.

    [column]   height (m), width (m, = 4b), thickness (m, default pi * width / 4: the half
               column then has the mass of a half circular column), cracked (default true),
               top_load (N, default 0: a dead load on the capital, e.g. an architrave; a
               uniform pressure on the top in the FEM, half of it at the top of each rigid half)
    [stone]    E (Pa), nu, density (kg/m^3), fc (Pa)            defaults: fem.assembly.Stone
    [[collar]] y, t, h, length, E, fy, pretension               as rigid.collars.Collar
    [ground]   pulse = "sine" | "cosine" | "record" | "none" (free rocking from [run]
               initial_tilt or initial_angular_velocity)
               amplitude (m/s^2) or amplitude_ratio (a_p / (g tan alpha) of the rocking half)
               period (s) or omega_ratio (Omega / p of the rocking half)
               record (file, PEER .AT2 or two columns), scale (default 1), time_scale
               (default 1; 2 plays the record twice as fast)
               vertical ground acceleration (upward positive), either harmonic:
               vertical_amplitude (m/s^2), vertical_period (s), vertical_phase (rad, default 0),
               vertical_duration (s, default: that of the horizontal motion), i.e.
               a_v sin(2 pi t / T + phase) on [0, duration]; or vertical_record (file) and
               vertical_scale (default 1)
    [contact]  friction (0.7), penalty_factor (1), penalty (N/m^3, optional), damping (0.05),
               friction_filter (s, 1e-3: low-pass time constant of the friction cone's normal force)
    [mesh]     size (m, default width / 16), grading (0.5), edge_length (m, default 0.1 x the
               width of a half: the toe length over which the edge stress is averaged),
               edge_time (s, default 2.5e-4: the time over which it is averaged too),
               toe_refinements (default [1, 2, 4, 8]: the cross-check reruns the impact that
               gives the peak toe stress with the toe zones refined so many times; [] for none),
               file (a quadrilateral mesh made elsewhere, e.g. gmsh .msh, instead of size/grading)
    [run]      duration (s, default end of the ground motion + 1.5 s), output_interval (s,
               default duration / 400), dt (s, default: the stable step), safety (0.9),
               initial_tilt (rad, default 0: the column released at t = 0 turned rigidly
               about the outer toe it tips on, > 0 toward +x, |tilt| < pi/4),
               initial_angular_velocity (rad/s, default 0, about that toe)

Unknown tables or keys and out-of-range values are errors naming the key.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from ..fem.assembly import Stone
from ..fem.model import ContactSettings
from ..fem.solver import EDGE_TIME
from ..fem.toe_stress import REFINEMENTS
from ..rigid.block import Block
from ..rigid.collars import collars_from_tables
from ..rigid.ground import (HarmonicPulse, NoMotion, Record, cosine_pulse, read_record,
                            sine_pulse)
from ..rigid.validation import InputError, read_toml, require_positive, require_range

SCHEMA = {
    "column": {"height", "width", "thickness", "cracked", "top_load"},
    "stone": {"E", "nu", "density", "fc"},
    "collar": None,          # array of tables, checked by rigid.collars
    "ground": {"pulse", "amplitude", "amplitude_ratio", "period", "omega_ratio", "record",
               "scale", "time_scale", "vertical_amplitude", "vertical_period", "vertical_phase",
               "vertical_duration", "vertical_record", "vertical_scale"},
    "contact": {"friction", "penalty_factor", "penalty", "damping", "friction_filter"},
    "mesh": {"size", "grading", "edge_length", "edge_time", "toe_refinements", "file"},
    "run": {"duration", "output_interval", "dt", "safety", "initial_tilt",
            "initial_angular_velocity"},
    "rigid": {"restitution", "model"},
    "study": {"name", "description", "kind"},
    "convergence": None,     # mesh-convergence studies, checked by studies.sweeps
}


@dataclass
class FemStudy:
    name: str
    height: float
    width: float
    thickness: float
    cracked: bool
    stone: Stone
    collars: tuple
    ground: object
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
    initial_tilt: float = 0.0                 # rad, theta sign
    initial_angular_velocity: float = 0.0     # rad/s
    source: str = ""
    edge_time: float = EDGE_TIME              # s
    toe_refinements: tuple = REFINEMENTS
    top_load: float = 0.0                     # N, on the capital
    vertical: object = None                   # vertical ground motion (rigid.ground), or None

    @property
    def rocking_block(self) -> Block:
        """The rigid block that rocks: one half of a cracked column, or the whole column."""
        b = self.width / (4.0 if self.cracked else 2.0)
        mass = self.stone.density * 2.0 * b * self.height * self.thickness
        return Block(b=b, h=0.5 * self.height, mass=mass,
                     restitution=self.rigid.get("restitution"),
                     top_load=self.top_load / (2.0 if self.cracked else 1.0))

    @property
    def column_block(self) -> Block:
        """The whole column as one rigid block (4b wide), with the whole top load."""
        mass = self.stone.density * self.width * self.height * self.thickness
        return Block(b=0.5 * self.width, h=0.5 * self.height, mass=mass,
                     restitution=self.rigid.get("restitution"), top_load=self.top_load)


def _toe_refinements(value) -> tuple:
    """[] or 1, 2, 4, ... (at least three, at most 16)."""
    allowed = "[] or [1, 2, 4] or [1, 2, 4, 8] or [1, 2, 4, 8, 16]"
    if not isinstance(value, list) or any(isinstance(v, bool) or not isinstance(v, int)
                                          for v in value):
        raise InputError(f"mesh.toe_refinements = {value!r} must be a list of integers: "
                         f"{allowed}")
    if value and (len(value) < 3 or value != [2 ** k for k in range(len(value))]
                  or value[-1] > 16):
        raise InputError(f"mesh.toe_refinements = {value!r} must be {allowed}")
    return tuple(value)


def toe_mesh(study: FemStudy, refinement: int):
    """The study's generated mesh with its toe zones (edge_length from each base corner)
    refined ``refinement`` times."""
    from ..meshes.column import column_mesh
    return column_mesh(study.width, study.height, study.mesh_size, cracked=study.cracked,
                       grading=study.grading, pinned_heights=[c.y for c in study.collars],
                       toe_refinement=refinement, toe_zone=study.edge_length)


def load(path) -> FemStudy:
    path = Path(path)
    return from_dict(read_toml(path, "study file"), source=str(path), base=path.parent)


def _check_keys(data: dict, source: str) -> None:
    for table, value in data.items():
        if table not in SCHEMA:
            raise InputError(f"{source}: unknown table [{table}] (allowed: "
                             f"{', '.join(sorted(SCHEMA))})")
        allowed = SCHEMA[table]
        if allowed is None:
            continue
        if not isinstance(value, dict):
            raise InputError(f"{source}: [{table}] must be a table")
        for key in value:
            if key not in allowed:
                raise InputError(f"{source}: unknown key {table}.{key} (allowed in [{table}]: "
                                 f"{', '.join(sorted(allowed))})")


def _number(table: dict, key: str, where: str, default=None):
    value = table.get(key, default)
    if value is None:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{where}.{key} = {value!r} is not a number")
    if not math.isfinite(value):
        raise InputError(f"{where}.{key} = {value!r} is not a finite number")
    return float(value)


def from_dict(data: dict, source: str = "study", base: Path = Path(".")) -> FemStudy:
    _check_keys(data, source)
    column = data.get("column", {})
    for key in ("height", "width"):
        if key not in column:
            raise InputError(f"{source}: column.{key} is required")
    height = require_positive("column.height (m)", _number(column, "height", "column"))
    width = require_positive("column.width (m)", _number(column, "width", "column"))
    cracked = column.get("cracked", True)
    if not isinstance(cracked, bool):
        raise InputError(f"column.cracked = {cracked!r} must be true or false")
    thickness = require_positive("column.thickness (m)",
                                 _number(column, "thickness", "column", math.pi * width / 4.0))
    top_load = require_range("column.top_load (N)", _number(column, "top_load", "column", 0.0),
                             0.0, math.inf, closed_low=True, range_text="[0, inf)")
    stone_table = data.get("stone", {})
    stone = Stone(**{k: _number(stone_table, k, "stone") for k in stone_table})
    collars = collars_from_tables(data.get("collar", []), source=source)
    for i, collar in enumerate(collars, start=1):
        require_range(f"collar {i} y (m)", collar.y, 0.0, height, closed_high=True,
                      range_text=f"(0, {height:g}] (the column height)")
    contact_table = data.get("contact", {})
    contact = ContactSettings(**{k: _number(contact_table, k, "contact") for k in contact_table})
    mesh = data.get("mesh", {})
    body_width = width / (2.0 if cracked else 1.0)
    size = _number(mesh, "size", "mesh", width / 16.0)
    require_range("mesh.size (m)", size, 0.0, body_width, closed_high=True,
                  range_text=f"(0, {body_width:g}] (the width of one half)")
    grading = require_range("mesh.grading", _number(mesh, "grading", "mesh", 0.5), 0.0, 1.0,
                            closed_low=True)
    edge_length = _number(mesh, "edge_length", "mesh", 0.1 * body_width)
    require_range("mesh.edge_length (m)", edge_length, 0.0, body_width, closed_high=True)
    edge_time = require_range("mesh.edge_time (s)", _number(mesh, "edge_time", "mesh", EDGE_TIME),
                              0.0, 0.01, closed_low=True, closed_high=True,
                              range_text="[0, 0.01] s")
    toe_refinements = _toe_refinements(mesh.get("toe_refinements", list(REFINEMENTS)))
    mesh_file = None
    if "file" in mesh:
        mesh_file = (base / str(mesh["file"])).resolve()
        if not mesh_file.is_file():
            raise InputError(f"mesh.file = {mesh['file']!r}: no such file")
    rigid = dict(data.get("rigid", {}))
    study = FemStudy(name=str(data.get("study", {}).get("name", Path(source).stem)),
                     height=height, width=width, thickness=thickness, cracked=cracked,
                     stone=stone, collars=collars, ground=None, contact=contact,
                     mesh_size=size, grading=grading, mesh_file=mesh_file,
                     edge_length=edge_length, duration=0.0,
                     output_interval=None, dt=None, safety=0.9, rigid=rigid, source=source,
                     edge_time=edge_time, toe_refinements=toe_refinements, top_load=top_load)
    study.ground = _ground(data.get("ground", {}), study.rocking_block, base, source)
    study.vertical = _vertical(data.get("ground", {}), study.ground, study.rocking_block, base,
                               source)
    run = data.get("run", {})
    end = max(study.ground.end_time, 0.0 if study.vertical is None else study.vertical.end_time)
    duration = _number(run, "duration", "run", end + 1.5)
    study.duration = require_positive("run.duration (s)", duration)
    study.output_interval = _number(run, "output_interval", "run")
    if study.output_interval is not None:
        require_positive("run.output_interval (s)", study.output_interval)
    study.dt = _number(run, "dt", "run")
    if study.dt is not None:
        require_positive("run.dt (s)", study.dt)
    study.safety = require_range("run.safety", _number(run, "safety", "run", 0.9), 0.0, 1.0,
                                 closed_high=True)
    study.initial_tilt = require_range("run.initial_tilt (rad)",
                                       _number(run, "initial_tilt", "run", 0.0),
                                       -0.25 * math.pi, 0.25 * math.pi,
                                       range_text="(-pi/4, pi/4)")
    study.initial_angular_velocity = _number(run, "initial_angular_velocity", "run", 0.0)
    if not math.isfinite(study.initial_angular_velocity):
        raise InputError("run.initial_angular_velocity is not a finite number")
    if (isinstance(study.ground, NoMotion) and study.initial_tilt == 0.0
            and study.initial_angular_velocity == 0.0):
        raise InputError(f"{source}: ground.pulse = 'none' needs run.initial_tilt or "
                         "run.initial_angular_velocity (else the column stays at rest)")
    return study


def _vertical(table: dict, horizontal, block: Block, base: Path, source: str):
    """The vertical ground motion of [ground] vertical_* (None without one)."""
    keys = {k for k in table if k.startswith("vertical_")}
    if not keys:
        return None
    if "vertical_record" in keys:
        extra = sorted(keys - {"vertical_record", "vertical_scale"})
        if extra:
            raise InputError(f"{source}: ground.{extra[0]} has no meaning with "
                             "ground.vertical_record")
        record = read_record(base / table["vertical_record"], g=block.g)
        return record.scaled(_number(table, "vertical_scale", "ground", 1.0))
    for key in ("vertical_amplitude", "vertical_period"):
        if key not in keys:
            raise InputError(f"{source}: ground.{key} is required for a vertical pulse (or "
                             "give ground.vertical_record)")
    if "vertical_scale" in keys:
        raise InputError(f"{source}: ground.vertical_scale goes with ground.vertical_record")
    amplitude = _number(table, "vertical_amplitude", "ground")
    require_range("ground.vertical_amplitude (m/s^2)", abs(amplitude), 0.0, 10.0 * block.g,
                  closed_low=True, range_text=f"|a_v| < 10 g = {10.0 * block.g:g}")
    period = require_positive("ground.vertical_period (s)",
                              _number(table, "vertical_period", "ground"))
    phase = _number(table, "vertical_phase", "ground", 0.0)
    default_duration = horizontal.end_time if horizontal.end_time > 0.0 else period
    duration = require_positive("ground.vertical_duration (s)",
                                _number(table, "vertical_duration", "ground",
                                        default_duration))
    return HarmonicPulse("sine", float(amplitude), 2.0 * math.pi / period, float(phase),
                         float(duration))


def _ground(table: dict, block: Block, base: Path, source: str):
    table = {k: v for k, v in table.items() if not k.startswith("vertical_")}
    kind = table.get("pulse", "sine")
    if kind not in ("sine", "cosine", "record", "none"):
        raise InputError(f"ground.pulse = {kind!r} is not one of sine, cosine, record, none")
    if kind == "none":
        extra = sorted(set(table) - {"pulse"})
        if extra:
            raise InputError(f"{source}: ground.{extra[0]} has no meaning with pulse = 'none'")
        return NoMotion()
    if kind == "record":
        if "record" not in table:
            raise InputError(f"{source}: ground.record (file) is required with pulse = 'record'")
        record = read_record(base / table["record"], g=block.g)
        speed = require_positive("ground.time_scale",
                                 _number(table, "time_scale", "ground", 1.0))
        if speed != 1.0:                 # t -> t / time_scale: the record played faster
            record = Record(record.time / speed, record.acceleration_values, record.name)
        return record.scaled(_number(table, "scale", "ground", 1.0))
    uplift = block.uplift_acceleration("nonlinear")
    if ("amplitude" in table) == ("amplitude_ratio" in table):
        raise InputError(f"{source}: give exactly one of ground.amplitude (m/s^2) and "
                         "ground.amplitude_ratio")
    if "amplitude" in table:
        amplitude = _number(table, "amplitude", "ground")
    else:
        ratio = _number(table, "amplitude_ratio", "ground")
        if not ratio >= 1.0:
            raise InputError(f"ground.amplitude_ratio = {ratio:g} is below uplift: it must be "
                             ">= 1")
        amplitude = ratio * uplift
    if ("period" in table) == ("omega_ratio" in table):
        raise InputError(f"{source}: give exactly one of ground.period (s) and "
                         "ground.omega_ratio")
    if "period" in table:
        omega = 2.0 * math.pi / require_positive("ground.period (s)",
                                                 _number(table, "period", "ground"))
    else:
        omega = require_positive("ground.omega_ratio",
                                 _number(table, "omega_ratio", "ground")) * block.p
    if abs(amplitude) < uplift:
        raise InputError(f"ground.amplitude = {amplitude:g} m/s^2 is below the uplift "
                         f"acceleration g tan(alpha) = {uplift:g} m/s^2 of the rocking half")
    make = sine_pulse if kind == "sine" else cosine_pulse
    return make(amplitude, omega, uplift)


def build(study: FemStudy):
    """Mesh and model of the study."""
    from ..fem.model import build_model

    if study.mesh_file is not None:
        from ..meshes.io import read
        mesh = read(study.mesh_file)
        for name, value, expected in (("width", mesh.width, study.width),
                                      ("height", mesh.height, study.height)):
            if abs(value - expected) > 1e-6 * expected:
                raise InputError(f"mesh.file {study.mesh_file.name}: its {name} {value:g} m "
                                 f"differs from column.{name} = {expected:g} m")
        if mesh.cracked != study.cracked:
            raise InputError(f"mesh.file {study.mesh_file.name} has {mesh.n_bodies} bodies but "
                             f"column.cracked = {str(study.cracked).lower()}")
    else:
        mesh = toe_mesh(study, 1)
    return build_model(mesh, study.stone, study.thickness, study.collars, study.contact,
                       top_load=study.top_load)


def run_study(study: FemStudy, out_dir=None, progress: bool = True):
    from ..fem.solver import run

    model = build(study)
    return run(model, study.ground, study.duration, dt=study.dt, safety=study.safety,
               output_interval=study.output_interval, edge_length=study.edge_length,
               edge_time=study.edge_time, out_dir=out_dir, vertical=study.vertical,
               progress=progress, initial_tilt=study.initial_tilt,
               initial_angular_velocity=study.initial_angular_velocity)
