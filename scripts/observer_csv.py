"""Reading the observer and load CSV files of a run (observers.csv, loads.csv) for the scripts
beside it: lines starting with '#' are comments, the first other line is the header, which must
name a column 'time'; every field a number. A bad file is one line through the caller's
`fail(message)` (which does not return), naming the file and the row or column."""
import csv


def read_columns(path, fail):
    """The header and the columns of a CSV file by name (floats), skipping '#' comment lines."""
    try:
        with open(path, newline="") as f:
            lines = [line for line in f if not line.lstrip().startswith("#") and line.strip()]
    except OSError as e:
        fail(f"{path}: cannot read the file ({e.strerror})")
    if not lines:
        fail(f"{path}: no header line")
    reader = csv.reader(lines)
    header = [name.strip() for name in next(reader)]
    if "time" not in header:
        fail(f"{path}: no column 'time' in the header {header}")
    columns = {name: [] for name in header}
    for number, row in enumerate(reader, start=2):
        if len(row) != len(header):
            fail(f"{path}: data row {number - 1} has {len(row)} fields, the header {len(header)}")
        for name, field in zip(header, row):
            try:
                columns[name].append(float(field))
            except ValueError:
                fail(f"{path}: data row {number - 1}, column '{name}': '{field.strip()}' is not a number")
    return header, columns
