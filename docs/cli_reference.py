"""The command-line reference page, generated from colonna's argparse parser.

``markdown(parser)`` walks ``colonna.studies.cli.build_parser()``: one section per subcommand
with its help, its usage line and a table of its options (names, choices or value, default,
help), so the page cannot drift from the parser. ``docs/conf.py`` writes it to
``docs/generated/cli.md`` at every build; ``tests/test_docs.py`` checks that it lists every
subcommand and every option.
"""

from __future__ import annotations

import argparse
import os
import re


def subcommands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    """The parser's subcommands by name, in the order they were added."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return dict(action.choices)
    return {}


def _helps(parser: argparse.ArgumentParser) -> dict[str, str]:
    """Each subcommand's one-line help, as ``colonna --help`` lists it."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return {choice.dest: choice.help or "" for choice in action._choices_actions}
    return {}


def _cell(text: str) -> str:
    """A table cell: one line, its option names as code (Markdown would make -- a dash)."""
    text = " ".join(str(text).split()).replace("|", "\\|")
    return re.sub(r"(?<![\w`])(--[a-z][a-z-]*)", r"`\1`", text)


def _value(action: argparse.Action) -> str:
    """What the option takes: its choices, its metavar or nothing (a flag)."""
    if action.nargs == 0:
        return "(flag)"
    if action.choices is not None:
        return " \\| ".join(f"`{c}`" for c in action.choices)
    metavar = action.metavar or action.dest.upper()
    return f"`{metavar} ...`" if action.nargs in ("+", "*") else f"`{metavar}`"


def _default(action: argparse.Action) -> str:
    if action.required:
        return "required"
    if action.nargs == 0 or action.default in (None, [], argparse.SUPPRESS):
        return ""
    return f"`{action.default}`"


def _options_table(parser: argparse.ArgumentParser) -> list[str]:
    """One table per argument group (positional, options, then the named groups)."""
    lines: list[str] = []
    for group in parser._action_groups:
        actions = [
            a
            for a in group._group_actions
            if not isinstance(a, argparse._HelpAction | argparse._SubParsersAction)
        ]
        if not actions:
            continue
        if group.title not in ("options", "optional arguments"):
            lines += [f"{_cell(group.title[0].upper() + group.title[1:])}:", ""]
        lines += ["| option | takes | default | meaning |", "|---|---|---|---|"]
        for action in actions:
            names = ", ".join(f"`{name}`" for name in action.option_strings) or f"`{action.dest}`"
            takes = _value(action) if action.option_strings else "positional"
            meaning = _cell(action.help or "")
            lines.append(f"| {names} | {takes} | {_default(action)} | {meaning} |")
        lines.append("")
    return lines


def markdown(parser: argparse.ArgumentParser) -> str:
    """The reference page of ``parser`` (``colonna``) as MyST Markdown, its usage lines wrapped
    at 72 columns (argparse reads the width from COLUMNS) to fit the page."""
    columns = os.environ.get("COLUMNS")
    os.environ["COLUMNS"] = "72"
    try:
        return _markdown(parser)
    finally:
        if columns is None:
            del os.environ["COLUMNS"]
        else:
            os.environ["COLUMNS"] = columns


def _markdown(parser: argparse.ArgumentParser) -> str:
    helps = _helps(parser)
    lines = [
        "# Command-line reference",
        "",
        "Generated from the argparse parser of `colonna` (`colonna.studies.cli.build_parser`) "
        "when the documentation is built. The [command-line guide](../command-line.md) shows "
        "examples and the conventions every command shares.",
        "",
        "```text",
        parser.format_usage().strip(),
        "```",
        "",
        *_options_table(parser),
        "",
    ]
    for name, sub in subcommands(parser).items():
        lines += [
            f"## colonna {name}",
            "",
            (helps.get(name) or sub.description or "").rstrip(".") + ".",
            "",
            "```text",
            sub.format_usage().strip(),
            "```",
            "",
            *_options_table(sub),
            "",
        ]
    return "\n".join(lines)
