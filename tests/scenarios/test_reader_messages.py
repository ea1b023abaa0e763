"""Readers that fail in one line: every case ends in exit 2 with one line naming the cause, never exit 4,
under GYROBENCH_MEMORY_LIMIT=100M; control characters never reach the terminal or a report raw; a full
disk names the target, not the folder being filled."""

from __future__ import annotations

import errno
import json
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

from gyrobench.base.atomic import AtomicWriteError
from gyrobench.scenarios.reports import outputs, report
from tests.scenarios.test_cli import assert_one_line_error, run

pytestmark = pytest.mark.usefixtures("user_files")

ROWS = "\n".join(f"{i / 100:.2f},{0.01 * np.sin(i):.6f}" for i in range(3000)) + "\n"


@pytest.fixture(autouse=True)
def _small_memory(monkeypatch):
    monkeypatch.setenv("GYROBENCH_MEMORY_LIMIT", "100M")


@pytest.mark.slow  # 60 MB files: seconds of the default tier; CI runs it
def test_a_60_mb_line_is_one_line(tmp_path, capsys, monkeypatch):
    p = tmp_path / "long.csv"
    p.write_text("time [s],gyro [deg/s]\n" + "1" * 60_000_000 + ",2\n" + ROWS)
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "more than the limit of 100 MB")  # refused by its size first
    monkeypatch.setenv("GYROBENCH_MEMORY_LIMIT", "2G")  # with room for it: refused by the line's length
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "line 2 has 60000002 bytes")


def test_a_1_mb_column_name_is_one_line(tmp_path, capsys):
    p = tmp_path / "name.csv"
    p.write_text("time [s],gyro_" + "z" * 1_000_000 + "\n" + ROWS)
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "line 1 has 1000014 bytes")
    p.write_text("time [s],gyro_" + "z" * 5000 + "\n" + ROWS)  # under the line limit: the name's own limit
    code, _, err = run(["allan", p], capsys)
    assert_one_line_error(code, err, "the name of column 1 has 5005 characters")


def test_a_deeply_nested_part_toml_is_one_line(tmp_path, capsys):
    part = tmp_path / "deep.toml"
    part.write_text("a = " + "[" * 5000 + "]" * 5000 + "\n")
    code, _, err = run(["simulate", "device", part, "--duration", "10s", "-o", tmp_path / "x.h5"], capsys)
    assert_one_line_error(code, err, "nests arrays or tables too deeply")
    real = tmp_path / "real.csv"
    real.write_text("time [s],gyro_z [deg/s]\n" + ROWS)
    code, _, err = run(["twin", real, "--part", part, "-o", tmp_path / "t.h5"], capsys)
    assert_one_line_error(code, err, "nests arrays or tables too deeply")


def _big_attribute(path: Path) -> Path:
    with h5py.File(path, "w") as f:
        f.attrs["format"] = "gyrobench-recording"
        f.attrs["format_version"] = 1
        g = f.create_group("recordings/r")
        g.attrs.update({"fs": 10.0, "t0": 0.0, "n_samples": 4000})
        g.attrs["metadata"] = json.dumps({"x": "a" * 60_000_000})
        g.create_group("truth")
        g.create_group("channels").create_dataset("rate", data=np.zeros(4000)).attrs["unit"] = "rad/s"
    return path


@pytest.mark.slow  # 60 MB files: seconds of the default tier; CI runs it
def test_a_60_mb_hdf5_attribute_is_refused_within_the_memory_limit(tmp_path):
    """The peak memory of the refusal (the process's maximum resident size) stays under the 100 MB limit."""
    big = _big_attribute(tmp_path / "big.h5")
    # VmHWM: the peak resident size of this process image (ru_maxrss would carry the parent's over exec)
    code = ("import re, sys\nfrom gyrobench.scenarios.cli.main import main\nc = main(['allan', sys.argv[1]])\n"
            "hwm = re.search(r'VmHWM:\\s+(\\d+)', open('/proc/self/status').read()).group(1)\n"
            "print(hwm, file=sys.stderr)\nsys.exit(c)\n")
    res = subprocess.run([sys.executable, "-c", code, str(big)], capture_output=True, text=True, timeout=120,
                         env={**__import__("os").environ, "GYROBENCH_MEMORY_LIMIT": "100M"})
    err, peak_kb = res.stderr.strip().splitlines()
    assert res.returncode == 2 and err.startswith("gyrobench: error: reading the attributes of"), res.stderr
    assert int(peak_kb) < 100_000, f"peak {int(peak_kb) / 1e3:.0f} MB"


@pytest.mark.parametrize(("rows", "says"), [
    ("time gyro\n" + "\n".join(f"{i / 100} {0.1 * i}" for i in range(50)), "separated by spaces"),
    ("time;gyro\n" + "\n".join(f"{i / 100};1,234.5" for i in range(50)), "thousand separators are not numbers"),
    ("time,gyro\n" + "\n".join(f"{float(i).hex()},{0.5.hex()}" for i in range(50)), "hex floats"),
    ("time [s],gyro [deg/s]\n" + "\n".join(f"{i / 100},\u22120.{i % 9 + 1}" for i in range(50)), "U+2212"),
])
def test_numbers_in_a_form_not_read_are_named(rows, says, tmp_path, capsys):
    p = tmp_path / "x.csv"
    p.write_text(rows + "\n", encoding="utf-8")
    code, _, err = run(["allan", p, "--units", "deg/s"], capsys)
    assert_one_line_error(code, err, says)
    assert "0 data rows" not in err


def test_control_characters_are_escaped_on_the_terminal(tmp_path, capsys):
    p = tmp_path / "esc.csv"
    p.write_text("time [s],gyro\x1b[2J\x07 [deg/s]\n" + ROWS)
    code, out, err = run(["allan", p, "--accept-nonstationary"], capsys)
    assert code == 0, err
    assert "\x1b" not in out and "\x07" not in out and "gyro\\x1b[2J\\x07" in out
    code, out, err = run(["allan", p, "--column", "nope\x1b]0;title\x07"], capsys)
    assert_one_line_error(code, err, "nope\\x1b]0;title\\x07")
    assert "\x1b" not in err and "\x07" not in err


def test_control_characters_are_escaped_in_the_report(tmp_path):
    report._write_text(tmp_path / "report.md", "label \x1b[31mred\x07\n")
    report._write_text(tmp_path / "index.html", "<p>label \x1b[31mred\x07</p>\n")
    for name in ("report.md", "index.html"):
        text = (tmp_path / name).read_text()
        assert "\x1b" not in text and "\x07" not in text and "\\x1b[31mred\\x07" in text


def test_a_full_disk_names_the_report_not_its_temporary_folder(tmp_path, monkeypatch):
    out = tmp_path / "rep"

    def full(outcomes, folder, *, command="", maps=None):
        target = Path(folder) / "index.html"
        raise AtomicWriteError(errno.ENOSPC, f"cannot write {str(target)!r}: No space left on device (the disk "
                                             "is full)", str(target))

    monkeypatch.setattr(report, "write_report", full)
    with pytest.raises(OSError) as info:
        outputs.write_report_as_a_set([], out)
    assert str(out / "index.html") in str(info.value) and ".tmpdir" not in str(info.value)
    assert not out.exists()
