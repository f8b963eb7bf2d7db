"""The command-line options of a rocking block and its collars, shared by the commands that run
one (``colonna rigid``, ``spectrum``, ``design`` and a kind's own, ``colonna fragility``): the
block by --p and --alpha or --b and --h, its mass, restitution, model and gravity; the collars as a
TOML file of [[collar]] tables. Their ranges are the study file's (:mod:`studies.schema`).
"""

from __future__ import annotations

import argparse
import dataclasses
import math
from pathlib import Path

from ..core.constants import STANDARD_GRAVITY
from ..core.errors import InputError, require_range
from ..rigid.block import MODELS, Block
from . import schema


def add_block_options(parser: argparse.ArgumentParser) -> None:
    """The block's options (read by :func:`block_from_args`)."""
    g = parser.add_argument_group("block (give --p and --alpha, or --b and --h)")
    g.add_argument("--p", type=float, help="frequency parameter p (rad/s)")
    g.add_argument("--alpha", type=float, help="slenderness angle alpha (rad), in (0, pi/2)")
    g.add_argument("--b", type=float, help="half width b of the rocking block (m)")
    g.add_argument("--h", type=float, help="half height h of the rocking block (m)")
    g.add_argument("--mass", type=float, help="block mass (kg); needed with collars")
    g.add_argument("--density", type=float, help="stone density (kg/m^3), instead of --mass")
    g.add_argument(
        "--thickness",
        type=float,
        help="out-of-plane thickness (m) with --density (default pi b: the mass of a "
        "half circular column)",
    )
    g.add_argument(
        "--restitution",
        type=float,
        help="coefficient of restitution nu (default Housner's 1 - 1.5 sin^2 alpha)",
    )
    g.add_argument(
        "--model",
        choices=MODELS + ("multibody",),
        default="nonlinear",
        help="linear or nonlinear: the SDOF rocking equation; multibody: rigid "
        "bodies with contact and friction (default nonlinear)",
    )
    g.add_argument(
        "--g",
        type=float,
        default=STANDARD_GRAVITY,
        help=f"gravity (m/s^2), default {STANDARD_GRAVITY:g}",
    )
    g.add_argument(
        "--top-load",
        type=float,
        default=0.0,
        help="dead load on the top of the block (N, default 0; needs --mass or "
        "--density): an architrave or arch springing, without mass",
    )


def block_from_args(args) -> Block:
    """The rocking block of the options: by p and alpha (Housner's p = sqrt(m g R / J0),
    alpha = atan(b / h)) or by b and h, with a mass or a density and thickness; each number
    within the study file's range of the same quantity."""
    by_ratio = args.p is not None or args.alpha is not None
    by_size = args.b is not None or args.h is not None
    if by_ratio and by_size:
        raise InputError("give either --p and --alpha or --b and --h, not both")
    if by_ratio:
        if args.p is None or args.alpha is None:
            raise InputError("--p and --alpha must be given together")
        block = Block.from_dimensionless(args.p, args.alpha, restitution=args.restitution, g=args.g)
        b, h = block.b, block.h
    elif by_size:
        if args.b is None or args.h is None:
            raise InputError("--b and --h must be given together")
        b, h = args.b, args.h
        # the study file's hard ranges of a column (width 4b, height 2h)
        low, high = schema.hard_range(schema.Column, "width")
        require_range("--b", b, low / 4.0, high / 4.0, closed_low=True, closed_high=True)
        low, high = schema.hard_range(schema.Column, "height")
        require_range("--h", h, low / 2.0, high / 2.0, closed_low=True, closed_high=True)
    else:
        raise InputError("the block is not given: use --p and --alpha, or --b and --h")
    if args.mass is not None and args.density is not None:
        raise InputError("give either --mass or --density, not both")
    if args.density is not None:
        # as a study file's stone.density: past it the mass overflows
        low, high = schema.hard_range(schema.Stone, "density")
        require_range("--density", args.density, low, high, closed_low=True, closed_high=True)
        thickness = args.thickness if args.thickness is not None else math.pi * b
        block = Block.from_density(
            b, h, args.density, thickness, restitution=args.restitution, g=args.g
        )
        return dataclasses.replace(block, top_load=args.top_load)
    return Block(
        b=b, h=h, mass=args.mass, restitution=args.restitution, g=args.g, top_load=args.top_load
    )


def add_collar_option(parser) -> None:
    """--collars, a collar file (read by :func:`collars_from_args`)."""
    parser.add_argument(
        "--collars",
        type=Path,
        help="TOML file with [[collar]] tables, the keys of a study file's [[collar]] ("
        + ", ".join(schema.Collar.model_fields)
        + "; docs/study-file.md); the block is then one half of the cracked column",
    )


def collars_from_args(args):
    """The collars of --collars (:func:`studies.schema.read_collars`), none without it."""
    return schema.read_collars(args.collars) if args.collars else ()
