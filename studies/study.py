"""The study: one study file, read once and validated once, with every default resolved.

:func:`load` is the one place a study file is read for a run. What it gives, a frozen
:class:`Study`, flows from there to the kind's runner (:data:`studies.kinds.KINDS`), to the
record of the inputs beside the results (``inputs.json`` is :meth:`Study.to_json`) and to the
report. The FEM column it describes is :attr:`Study.fem` (a
:class:`studies.fem_study.FemStudy`), built from the validated file without validating it
again; a case carries ``study.fem.to_json()`` to its worker, which rebuilds it with
:meth:`FemStudy.from_json <studies.fem_study.FemStudy.from_json>`.

>>> from importlib.resources import files
>>> study = load(files("colonna.studies") / "default.toml")
>>> study.kind, study.fem.cracked, round(study.fem.thickness, 4)
('cross-check', True, 0.3534)
>>> study.to_json()["column"]["thickness"] == study.fem.thickness
True
"""

from __future__ import annotations

import copy
import hashlib
import importlib
import math
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any

from ..core.errors import read_toml_bytes
from . import schema


@dataclass(frozen=True, eq=False)
class Study:
    """A study file as its kind runs it: ``path``, the file's bytes (``text``, put on record
    byte for byte), its tables with the kind's own defaults (``data``, what variants of it are
    made from: :func:`studies.schema.variant`), the validated file (``spec``) and the command
    line ``options`` that change what is computed (given ones only)."""

    path: Path
    text: bytes = field(repr=False)
    data: dict = field(repr=False)
    spec: schema.StudyFile = field(repr=False)
    options: dict = field(default_factory=dict)

    @property
    def kind(self) -> str:
        """The study kind (``[study] kind``), a name of :data:`studies.kinds.KINDS`."""
        return self.spec.study.kind

    @property
    def source(self) -> str:
        """The study file's path as given: how messages name it."""
        return str(self.path)

    @property
    def base(self) -> Path:
        """The folder the files a study names (records, meshes) are found relative to."""
        return self.path.parent

    @property
    def sha256(self) -> str:
        """The SHA-256 of the study file's bytes."""
        return hashlib.sha256(self.text).hexdigest()

    @cached_property
    def fem(self):
        """The column, its collars, ground motion and run settings, built once from the
        validated file (:func:`studies.fem_study.from_spec`; an InputError where the file
        describes no column this kind can run, e.g. a pulse below the uplift acceleration)."""
        from .fem_study import from_spec

        return from_spec(self.spec, self.source, self.base)

    @cached_property
    def model(self) -> dict | None:
        """The FEM model of the study's own mesh as its runs build it
        (:func:`studies.models.model_record`: nodes, stable step, step used, penalties), built
        once; None for a kind that runs no FEM (its package has no ``fem_work``)."""
        from .fem_study import column_of
        from .models import model_record

        if self.spec.column is None or not _runs_fem(self.kind):
            return None
        column = column_of(self.spec, self.source, self.base)
        if _one_motion(self.kind):
            column = self.fem
        return model_record(column)

    def to_json(self) -> dict:
        """The inputs on record (``inputs.json``), in three parts.

        The study file's tables as the run used them: each key's value from the file, else
        its default (:mod:`studies.schema`), else the value colonna resolved for the run (the
        mesh size, the toe length, the stable step, the duration, a pulse's amplitude and
        period in SI, a record's scales, the rigid block's restitution, the [stone] keys a
        preset sets: ``resolved`` names each such key with the rule that gave it). A key
        without a value (not given, not used: a record file of a sine pulse) and the tables of
        other kinds are left out: no null.
        A re-run is keyed by the file (study.toml, byte for byte), not by this record.

        ``model``: the FEM model of the study's mesh as built (nodes, elements, stable step,
        penalties: :func:`studies.models.model_record`); ``ground_motion``: the motion as
        applied (SI; a record's file by its SHA-256, its peak as read and as applied).

        And the study file's name and SHA-256, the colonna version and the command-line
        ``options``. The run's date, machine and wall time are added beside the results
        (:func:`studies.output.record_inputs`)."""
        from .kinds import KINDS, kind_tables
        from .stone_presets import from_preset

        inputs = self.spec.model_dump(mode="json")
        resolved: dict[str, str] = {}
        for name in kind_tables():
            if name not in KINDS[self.kind].tables:
                inputs.pop(name, None)
        if inputs.get("column") is not None:
            self._resolve_column(inputs, resolved)
        stone = self.data.get("stone")
        for key, rule in from_preset(stone if isinstance(stone, dict) else {}).items():
            resolved[f"stone.{key}"] = rule  # a value of [stone] preset (studies.stone_presets)
        for key, rule in KINDS[self.kind].per_case_rules().items():
            table, name = key.split(".")
            inputs[table].pop(name, None)
            resolved[key] = rule
        inputs = _without_nulls(inputs)
        if self.model is not None:
            inputs["model"] = dict(self.model)
        motion = self._motion_record()
        if motion is not None:
            inputs["ground_motion"] = motion
        inputs.update(
            resolved=resolved,
            study_file=self.path.name,
            study_sha256=self.sha256,
            colonna_version=importlib.import_module("colonna").__version__,
            options={k: _option_text(v) for k, v in self.options.items() if v is not None},
        )
        return inputs

    def _resolve_column(self, inputs: dict, resolved: dict) -> None:
        """Fill in ``inputs``' tables the values resolved for a study with a column (see
        :meth:`to_json`), naming each in ``resolved`` with its rule."""
        from ..core.collar import Collar
        from ..core.errors import InputError
        from .fem_study import column_of

        def fill(table: str, key: str, value, rule: str) -> None:
            if inputs[table].get(key) is None and value is not None:
                inputs[table][key] = value
                resolved[f"{table}.{key}"] = rule

        column = column_of(self.spec, self.source, self.base)
        fill("column", "thickness", column.thickness, "pi width / 4 (a half column's mass)")
        for i, entry in enumerate(inputs["collar"]):
            if entry["length"] is None:  # between the attachment points: the width
                entry["length"] = column.width
                resolved[f"collar.{i}.length"] = "the column width (between its faces)"
            if entry["Eh"] is None:
                entry["Eh"] = Collar(**entry).hardening_modulus
                resolved[f"collar.{i}.Eh"] = "1 % of E"
            if entry["hinge_length"] is None:
                entry["hinge_length"] = entry["h"]
                resolved[f"collar.{i}.hinge_length"] = "the collar depth h"
            if entry.get("section") is None and entry["plastic"]:
                entry["section"] = "fibre"
                resolved[f"collar.{i}.section"] = "fibre (a plastic collar's default)"
        if _runs_fem(self.kind):  # the mesh a kind without FEM runs does not use
            if column.mesh_file is None:
                fill("mesh", "size", column.mesh_size, "width / 16")
            fill("mesh", "edge_length", column.edge_length, "a tenth of a rocking body's width")
            bed = column.bed
            fill(
                "base", "stiffness", bed.stiffness, f"the {inputs['base']['bed']} preset's nominal"
            )
            fill("base", "stiffness_range", [bed.low, bed.high], bed.source)
        try:
            nu = column.rocking_block.nu
        except InputError:  # a squat block: its SDOF run asks for a restitution
            nu = None
        fill("rigid", "restitution", nu, "Housner's 1 - 1.5 sin^2 alpha of the rocking block")
        model = self.model or {}
        fill("run", "dt", model.get("dt"), "the stable step (model.dt_stable)")
        if not _one_motion(self.kind):
            return
        fem = self.fem
        fill("run", "duration", fem.duration, "the end of the ground motion + 1.5 s")
        fill("run", "output_interval", fem.duration / 400.0, "duration / 400")
        ground = inputs["ground"]
        sine = fem.ground.sine_form  # a pulse: its amplitude and frequency in SI
        if sine is not None:
            rule = "amplitude_ratio x the rocking half's uplift acceleration"
            fill("ground", "amplitude", sine.amplitude, rule)
            period = 2.0 * math.pi / sine.omega
            fill("ground", "period", period, "2 pi / (omega_ratio x p of the rocking half)")
        if ground["pulse"] == "record":
            fill("ground", "scale", *self._record_scale())
            fill("ground", "time_scale", 1.0, "1 (the record's own time)")
        if ground.get("vertical_record") is not None:
            fill("ground", "vertical_scale", 1.0, "1 (the record as read)")

    def _record_scale(self) -> tuple[float, str]:
        """The factor on the horizontal record and how it was set
        (:func:`studies.fem_study.record_scale`)."""
        from .fem_study import played_record, record_scale

        ground = self.spec.ground
        return record_scale(ground, played_record(ground, self.base, self.source, schema.G))

    def _motion_record(self) -> dict | None:
        """The ground motion as applied (:meth:`to_json`'s ``ground_motion``), for a kind with
        one motion; a record's samples are not repeated (its file is named by its SHA-256)."""
        if self.spec.column is None or not _one_motion(self.kind):
            return None
        fem = self.fem
        record: dict = {}
        for name, motion, given, scale in (
            (
                "horizontal",
                fem.ground,
                self.spec.ground.record,
                self._record_scale()[0] if self.spec.ground.record is not None else None,
            ),
            (
                "vertical",
                fem.vertical,
                self.spec.ground.vertical_record,
                self.spec.ground.vertical_scale,
            ),
        ):
            if not motion.moves:
                continue
            entry = motion.to_json()
            for samples in ("time", "acceleration_values"):  # the file has them
                entry.pop(samples, None)
            entry.update(peak_acceleration=motion.peak_acceleration, end_time=motion.end_time)
            if given is not None:
                path = self.base / given
                factor = 1.0 if scale is None else abs(scale)
                entry.update(
                    file=given,
                    file_sha256=hashlib.sha256(path.read_bytes()).hexdigest(),
                    samples=int(len(motion.acceleration_table()[0])),
                )
                if factor > 0.0:  # the peak of the file as read (m/s^2), before ground.scale
                    entry["file_peak_acceleration"] = motion.peak_acceleration / factor
            record[name] = entry
        return record or None


def _runs_fem(kind: str) -> bool:
    """Whether a kind runs the FEM: its package estimates the FEM work it asks for
    (``fem_work``, :mod:`studies.kinds`)."""
    from .kinds import KINDS

    return getattr(KINDS[kind].module(), "fem_work", None) is not None


def _one_motion(kind: str) -> bool:
    """Whether a kind runs the study's one ground motion (its registry's ``ground_motion``)."""
    from .kinds import KINDS

    return KINDS[kind].ground_motion


def _without_nulls(data):
    """``data`` without the keys whose value is None or an empty table (nor such list items),
    recursively."""
    if isinstance(data, dict):
        kept = {k: _without_nulls(v) for k, v in data.items() if v is not None}
        return {k: v for k, v in kept.items() if v != {}}
    if isinstance(data, list):
        return [_without_nulls(v) for v in data if v is not None]
    return data


def _option_text(value: Any) -> Any:
    """A command-line option as on record: a grid (8, 8) as "8x8"."""
    return "x".join(map(str, value)) if isinstance(value, tuple) else value


def with_kind_defaults(data: dict) -> dict:
    """A study file's tables with its kind's own defaults (a kind's package may define
    ``defaults(data) -> data``; a free-rocking study has no ground motion and runs 3 s), any
    other as given (a copy either way)."""
    from .kinds import DEFAULT_KIND, KINDS

    data = copy.deepcopy(data)
    table = data.get("study")
    name = table.get("kind", DEFAULT_KIND) if isinstance(table, dict) else DEFAULT_KIND
    kind = KINDS.get(name) if isinstance(name, str) else None
    defaults = getattr(kind.module(), "defaults", None) if kind is not None else None
    return defaults(data) if defaults is not None else data


def load(path, options: dict | None = None) -> Study:
    """The study of a file, read once and validated once against :mod:`studies.schema` with
    its kind's defaults: every error of the file at once, one line each, in one InputError."""
    path = Path(path)
    text, data = read_toml_bytes(path, "study file")
    data = with_kind_defaults(data)
    spec = schema.parse(data, str(path))
    return Study(path, text, data, spec, dict(options or {}))
