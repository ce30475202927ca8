#!/usr/bin/env python3
"""Checks bench/results/paper_tables.csv, the one machine-readable table of the paper-table cells romp
reproduces (issue #33): its header, that every row names one of the three papers, that its numbers
parse, that no (paper, table, cell) appears twice, that every results folder exists and that every
command is one of the repository's tools or built binaries. Prints one summary line; exits 1 naming the
first bad row.

    check_paper_tables.py SOURCE_DIR [CSV]

CSV defaults to SOURCE_DIR/bench/results/paper_tables.csv (a second path is for testing the checker on a
broken copy). A row whose romp column is empty is an open cell (not reproduced yet): it may have no
command (where no romp command can produce it), but a measured row must have one.
"""
import csv
import math
import pathlib
import sys

HEADER = ["paper", "table", "cell", "romp", "paper_value", "unit", "command", "results_folder"]
PAPERS = {"rom", "enriched-mpm", "nclaw"}
COMMAND_PREFIXES = ("tools/", "build/")


def fail(message):
    print(f"check_paper_tables: {message}", file=sys.stderr)
    sys.exit(1)


def is_number(text):
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


def main():
    if len(sys.argv) not in (2, 3):
        fail("usage: check_paper_tables.py SOURCE_DIR [CSV]")
    root = pathlib.Path(sys.argv[1])
    path = pathlib.Path(sys.argv[2]) if len(sys.argv) == 3 else root / "bench/results/paper_tables.csv"
    if not path.is_file():
        fail(f"{path}: no such file")

    with open(path, newline="", encoding="utf-8") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header != HEADER:
            fail(f"{path}: header is {header}, expected {','.join(HEADER)}")
        rows = list(reader)
    if not rows:
        fail(f"{path}: no rows")

    seen = {}
    measured = 0
    for line, row in enumerate(rows, start=2):
        where = f"{path}:{line}"
        if len(row) != len(HEADER):
            fail(f"{where}: {len(row)} fields, expected {len(HEADER)}: {row}")
        record = dict(zip(HEADER, row))
        name = f"{record['paper']} / {record['table']} / {record['cell']}"
        if record["paper"] not in PAPERS:
            fail(f"{where} ({name}): paper '{record['paper']}' is not one of {', '.join(sorted(PAPERS))}")
        for field in ("table", "cell", "unit", "results_folder"):
            if not record[field].strip():
                fail(f"{where} ({name}): empty {field}")
        for field in ("romp", "paper_value"):
            if record[field] and not is_number(record[field]):
                fail(f"{where} ({name}): {field} '{record[field]}' is not a plain number")
        key = (record["paper"], record["table"], record["cell"])
        if key in seen:
            fail(f"{where} ({name}): the same cell as line {seen[key]}")
        seen[key] = line
        folder = record["results_folder"]
        if pathlib.PurePath(folder).is_absolute() or ".." in pathlib.PurePath(folder).parts:
            fail(f"{where} ({name}): results_folder '{folder}' must be a path inside the repository")
        if not folder.startswith("bench/results/"):
            fail(f"{where} ({name}): results_folder '{folder}' is not under bench/results/")
        if not (root / folder).exists():
            fail(f"{where} ({name}): results_folder '{folder}' does not exist under {root}")
        command = record["command"]
        if command and not command.startswith(COMMAND_PREFIXES):
            fail(f"{where} ({name}): command '{command}' does not start with {' or '.join(COMMAND_PREFIXES)}")
        if record["romp"]:
            measured += 1
            if not command:
                fail(f"{where} ({name}): a measured cell without the command that produces it")

    print(f"check_paper_tables: {path}: {len(rows)} rows, {measured} cells measured, "
          f"{len(rows) - measured} cells open")


if __name__ == "__main__":
    main()
