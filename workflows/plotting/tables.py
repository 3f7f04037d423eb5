"""Readers of the CSV outputs of mpm_solver (series.csv, tracked_points.csv) and small table writers."""
import csv
from pathlib import Path

import numpy as np


def complete_lines(file):
    """The header line and the complete rows of a CSV, as text; ValueError naming the file when it is
    empty. A last row without its line end is dropped: it is the row a killed run was writing."""
    file = Path(file)
    text = file.read_text()
    lines = text.splitlines()
    if len(lines) > 1 and not text.endswith("\n"):
        lines.pop()
    if not lines:
        raise ValueError(f"{file}: empty, expected a header line")
    return lines


def read_csv(file):
    """Column name → float array of a numeric CSV with a header line (complete_lines); ValueError
    naming the file when the header is missing or a row has the wrong number of fields."""
    file = Path(file)
    rows = list(csv.reader(complete_lines(file)))
    header = rows[0]
    for number, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise ValueError(f"{file}:{number}: expected {len(header)} fields, got {len(row)}")
    values = np.array([[float(x) for x in row] for row in rows[1:]]).reshape(-1, len(header))
    return {name: values[:, k] for k, name in enumerate(header)}


def split_by(table, key):
    """{value of column `key` → sub-table}: e.g. tracked_points.csv per point id."""
    return {int(v): {name: col[table[key] == v] for name, col in table.items()} for v in np.unique(table[key])}


def write_csv(file, rows):
    """rows: list of dicts with the same keys (the header, in the first row's order)."""
    with Path(file).open("w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def markdown(rows, formats=None):
    """A Markdown table of `rows` (dicts with the same keys, the header); formats: column → format spec
    (default: 4 significant digits for floats, str otherwise); None is written as "–" (not measured)."""
    columns = list(rows[0])
    lines = ["| " + " | ".join(columns) + " |", "|" + "---|" * len(columns)]
    for row in rows:
        cells = ("–" if row[c] is None else format(row[c], (formats or {}).get(c, ".4g" if isinstance(row[c], float) else ""))
                 for c in columns)
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def write_markdown(file, rows, formats=None):
    """markdown(rows, formats) into `file`."""
    Path(file).write_text(markdown(rows, formats))
