"""What the typed-summary tests share: every row of a report's Numbers table resolves against a
real summary.json of its kind (studies.sections)."""

import json
from pathlib import Path

from colonna.studies.report import get, has


def assert_rows_resolve(rows, load, out: Path) -> list[str]:
    """summary.json of ``out`` loads into its typed sections (``load``: a declared key the file
    lacks fails, named) and each row's Ref reads by attribute the value the file holds at the
    row's key, on the page (index.html) under that key; a row is left out only where the file
    has no value at its key. Returns the keys of the rows left out."""
    data = json.loads((out / "summary.json").read_text())
    typed = load(data)
    page = (out / "index.html").read_text()
    left_out = []
    for _, ref, _ in rows:
        assert ref.present(typed) == has(data, ref.key), ref.key
        if ref.present(typed):
            assert json.dumps(ref.of(typed)) == json.dumps(get(data, ref.key)), ref.key
            assert f'data-key="{ref.key}"' in page, ref.key
        else:
            left_out.append(ref.key)
    return left_out
