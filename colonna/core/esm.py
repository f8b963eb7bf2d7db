"""Accelerograms in the ESM ASCII format: the Engineering Strong-Motion database of ORFEUS
(esm-db.eu), which holds the Italian records, e.g. the 2012 Emilia sequence at Mirandola (MRN).

An ESM ASCII file (``.ASC``, also served as ``.txt``) holds one component: a header of
``KEY: value`` lines (64 in the database's ``HEADER_FORMAT: DYNA 1.2``: ``EVENT_NAME``,
``EVENT_ID``, ``NETWORK``, ``STATION_CODE``, ``STREAM``, ``SAMPLING_INTERVAL_S``, ``NDATA``,
``DATA_TYPE``, ``UNITS``, ``PGA_CM/S^2``, ...; a value may hold colons, the key ends at the
first), then the ``NDATA`` samples, one or more a line, ``SAMPLING_INTERVAL_S`` apart from
t = 0. The samples are in the header's ``UNITS`` (``cm/s^2`` in the database's acceleration
files). Only ``DATA_TYPE: ACCELERATION`` is a ground motion (velocity, displacement and spectra
files are refused with that reason). The header's ``PGA_CM/S^2`` is checked against the
largest |sample| (within 2 %), which catches a header whose units do not fit its samples.

The reader itself is :func:`colonna.core.ground.read_esm_file`, beside the PEER and two-column
readers, so that :func:`colonna.core.ground.read_record` reads an ESM file (``.asc``, or any file
that starts ``EVENT_NAME:``) without importing this module; here are its record and header.
"""

from __future__ import annotations

from dataclasses import dataclass, field

from .constants import STANDARD_GRAVITY
from .ground import Record, is_esm, read_esm_file

__all__ = ["EsmFile", "is_esm", "read", "read_file"]


@dataclass(frozen=True)
class EsmFile:
    """An ESM file read: its record (m/s^2) and its header (keys as written, values stripped)."""

    record: Record
    header: dict[str, str] = field(repr=False)

    @property
    def event(self) -> str:
        """``EVENT_NAME`` (empty where the header has none)."""
        return self.header.get("EVENT_NAME", "")

    @property
    def station(self) -> str:
        """``STATION_CODE`` (empty where the header has none)."""
        return self.header.get("STATION_CODE", "")

    @property
    def stream(self) -> str:
        """``STREAM``, the component (``HNE``, ``HNN``, ``HNZ``; empty where none)."""
        return self.header.get("STREAM", "")


def read_file(path, *, g: float = STANDARD_GRAVITY) -> EsmFile:
    """Read an ESM ASCII file: its record (m/s^2, named after the file) and its header."""
    record, header = read_esm_file(path, g=g)
    return EsmFile(record, header)


def read(path, *, g: float = STANDARD_GRAVITY) -> Record:
    """The record (m/s^2) of an ESM ASCII file, in the units its header states."""
    return read_esm_file(path, g=g)[0]
