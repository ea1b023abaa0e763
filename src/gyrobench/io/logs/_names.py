"""Column names and units of IMU logs: the header cell's name and unit, the time column, the quantity."""

from __future__ import annotations

import csv
import re

#: a time step larger than this multiple of the median step is a gap in the record
GAP_FACTOR = 1.5
#: fewer data rows than this cannot give any Allan deviation
MIN_ROWS = 2

#: time-column names (case-insensitive, after removing a "[unit]" or "(unit)")
_TIME_NAME = re.compile(
    r"^#?\s*(?:%?time|t|timestamp|times|field\.header\.stamp|stamp)(?:[ _-]?(s|sec|secs|seconds|ms|us|ns))?$",
    re.IGNORECASE,
)
#: time unit name -> seconds
TIME_UNITS = {
    "s": 1.0,
    "sec": 1.0,
    "secs": 1.0,
    "second": 1.0,
    "seconds": 1.0,
    "ms": 1e-3,
    "us": 1e-6,
    "µs": 1e-6,
    "ns": 1e-9,
    "min": 60.0,
    "h": 3600.0,
}
#: acceleration units -> m/s^2 (standard gravity 9.80665 m/s^2, CGPM 1901)
ACCEL_UNITS = {
    "m/s^2": 1.0,
    "m/s2": 1.0,
    "m s^-2": 1.0,
    "g": 9.80665,
    "mg": 9.80665e-3,
    "ug": 9.80665e-6,
}
#: spellings of rate units in real headers -> gyrobench.base.units.RATE_UNITS names
_RATE_ALIASES = {
    "rad s^-1": "rad/s",
    "rad/sec": "rad/s",
    "rad s-1": "rad/s",
    "dps": "deg/s",
    "deg/sec": "deg/s",
    "°/s": "deg/s",
    "deg s^-1": "deg/s",
    "dph": "deg/h",
    "°/h": "deg/h",
}
#: column-name patterns of gyro (rate) and accelerometer columns, for the all-axes mode
_GYRO_NAME = re.compile(r"(^w_|^omega|gyro|angular_velocity|^g[xyz]$|^w[xyz]$|rate)", re.IGNORECASE)
_ACCEL_NAME = re.compile(r"(^a_|^alpha_|acc|linear_acceleration|^a[xyz]$)", re.IGNORECASE)
#: names that are not a measured gyro or accelerometer axis although they match the patterns above or end
#: in an axis letter (the covariance and orientation fields of ROS sensor_msgs/Imu, e.g.
#: ``field.angular_velocity_covariance0``; quaternions, magnetometer axes, temperatures)
_NOT_AXIS_NAME = re.compile(r"covariance|orientation|quat|^mag|_mag|temp", re.IGNORECASE)
#: name suffixes that carry a unit (``gyro_x_dps``, ``accel_x_g``)
_SUFFIX_UNIT = {
    "dps": "deg/s",
    "degps": "deg/s",
    "radps": "rad/s",
    "rads": "rad/s",
    "dph": "deg/h",
    "g": "g",
    "mg": "mg",
    "mps2": "m/s^2",
    "ms2": "m/s^2",
}
#: formats whose columns have an implied SI unit
_SI_FORMATS = ("euroc", "kalibr", "ros")



# ----------------------------------------------------------------------------- header parsing
#: an ISO-8601 date-time as loggers write it: date, "T" or space, hh:mm[:ss[.fff]], optional Z or UTC offset
_ISO = re.compile(r"^\d{4}-\d{2}-\d{2}[T ]\d{2}:\d{2}(:\d{2}([.,]\d+)?)?(Z|[+-]\d{2}:?\d{2})?$")



def split_header(cell: str) -> tuple[str, str | None]:
    """``"gyro [deg/s]"`` or ``"Time (s)"`` -> (name, unit); the unit may itself hold parentheses."""
    cell = cell.strip()
    close = cell[-1:] if cell[-1:] in ")]" else None
    if close is None:
        return cell, None
    opening = "(" if close == ")" else "["
    depth = 0
    for i in range(len(cell) - 1, -1, -1):
        depth += (cell[i] == close) - (cell[i] == opening)
        if depth == 0:
            return cell[:i].strip(), cell[i + 1 : -1].strip() or None
    return cell, None


def time_column(
    names: list[str], hdr_units: list[str | None]
) -> tuple[int | None, float | None, bool]:
    """Index of the time column, its unit in s (None: not a time unit) and whether the unit was stated."""
    for i, nm in enumerate(names):
        m = _TIME_NAME.match(nm.strip())
        if m:
            unit = hdr_units[i] or m.group(1)
            if unit is None:
                return i, 1.0, False
            return i, TIME_UNITS.get(unit.lower()), True
    return None, None, False


def unit_of(name: str, hdr_unit: str | None, fmt: str) -> tuple[str | None, str | None]:
    """(quantity, unit) of a data column from its header unit, its name suffix or its format."""
    from gyrobench.base import units

    unit = hdr_unit
    if unit is not None:
        unit = _RATE_ALIASES.get(unit, unit)
        if unit in units.RATE_UNITS:
            return "rate", unit
        if unit in ACCEL_UNITS:
            return "accel", unit
        return None, unit
    suffix = name.rsplit("_", 1)[-1].lower() if "_" in name else ""
    if suffix in _SUFFIX_UNIT:
        u = _SUFFIX_UNIT[suffix]
        return ("accel" if u in ACCEL_UNITS else "rate"), u
    if fmt in _SI_FORMATS:
        if _GYRO_NAME.search(name):
            return "rate", "rad/s"
        if _ACCEL_NAME.search(name):
            return "accel", "m/s^2"
    if _ACCEL_NAME.search(name):
        return "accel", None
    return None, None


def _format_of(names: list[str]) -> str:
    low = [n.lower().lstrip("#").strip() for n in names]
    if any(n.startswith("w_rs_s_") for n in low):
        return "euroc"
    if any(n.startswith("field.angular_velocity") for n in low):
        return "ros"
    if "omega_x" in low and low[:1] == ["timestamp"]:
        return "kalibr"
    return "csv"


def _sniff_delimiter(line: str) -> str:
    """The separator of a header or data row: the most frequent of , ; tab outside quotes (comma on a tie)."""
    counts = {d: 0 for d in (",", ";", "\t")}
    quoted = False
    for ch in line:
        if ch == '"':
            quoted = not quoted
        elif not quoted and ch in counts:
            counts[ch] += 1
    best = max(counts, key=lambda d: (counts[d], d == ","))
    return best if counts[best] else ","


def _cells(line: str, delim: str) -> list[str]:
    try:
        return [
            c.strip()
            for c in next(csv.reader([line], delimiter=delim, quotechar='"', skipinitialspace=True))
        ]
    except csv.Error as exc:  # a cell past csv's field limit (the reader's line limit comes first)
        raise ValueError(f"a line of {len(line)} characters cannot be split into cells ({exc})") from None


#: characters that look like a minus sign but are not ASCII '-' (U+2212 minus, dashes, full-width)
_MINUS_LOOKALIKES = "\u2212\u2010\u2011\u2012\u2013\u2014\ufe63\uff0d"
_HEX_FLOAT = re.compile(r"^[+-]?0x[0-9a-f]*\.?[0-9a-f]*(p[+-]?\d+)?$", re.IGNORECASE)
_GROUPED = re.compile(r"^[+-]?\d{1,3}(?:([,.'\u00a0\u202f ])\d{3})(?:\1\d{3})*(?:[.,]\d+)?$")


def not_a_number_cause(cell: str) -> str:
    """Why ``cell`` looks like a number but is not one (a Unicode minus, a hex float, thousand separators),
    as a clause for a message; "" when it does not look like one."""
    s = cell.strip().strip('"')
    if any(c in s for c in _MINUS_LOOKALIKES) and _is_number(s.translate({ord(c): "-" for c in _MINUS_LOOKALIKES})):
        ch = next(c for c in s if c in _MINUS_LOOKALIKES)
        return (f"its minus sign is the Unicode character U+{ord(ch):04X}, not ASCII '-': replace it by '-' "
                "(spreadsheets and word processors write it)")
    if _HEX_FLOAT.match(s) and any(ch.isdigit() for ch in s):
        return "hex floats (such as 0x1.8p+3) are not read: write the numbers in decimal"
    if _GROUPED.match(s):
        return ("thousand separators are not numbers: export the numbers without digit grouping "
                "(1234.5, not 1,234.5)")
    return ""


def space_separated(line: str) -> bool:
    """Whether ``line`` is numbers separated by spaces only (no ',', ';' or tab): a column layout not read."""
    if any(d in line for d in ",;\t"):
        return False
    parts = line.split()
    return len(parts) >= 2 and all(_is_number(p) for p in parts)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True
