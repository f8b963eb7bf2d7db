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

    def to_json(self) -> dict:
        """The inputs on record (``inputs.json``): the validated study with every default
        filled in, the defaults that depend on the column resolved (thickness, collar length
        and hardening modulus), the study file's name and SHA-256, the colonna version and the
        ``options``."""
        from ..core.collar import Collar
        from .fem_study import default_thickness

        inputs = self.spec.model_dump(mode="json")
        column = inputs.get("column")
        if column is not None:
            if column["thickness"] is None:
                column["thickness"] = default_thickness(column["width"])
            for entry in inputs["collar"]:
                if entry["length"] is None:  # between the attachment points: the width
                    entry["length"] = column["width"]
                entry["Eh"] = Collar(**entry).hardening_modulus
        inputs.update(
            study_file=self.path.name,
            study_sha256=self.sha256,
            colonna_version=importlib.import_module("colonna").__version__,
            options={k: _option_text(v) for k, v in self.options.items() if v is not None},
        )
        return inputs


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
