"""benchmarks/bench_speed.py --splice: the generated table replaces what lies between the markers."""

from __future__ import annotations

import importlib.util
import os

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))


def _bench():
    path = os.path.join(HERE, "..", "benchmarks", "bench_speed.py")
    spec = importlib.util.spec_from_file_location("bench_speed_under_test", path)
    mod = importlib.util.module_from_spec(spec)
    assert spec.loader is not None
    spec.loader.exec_module(mod)
    return mod


def test_splice_replaces_only_between_the_markers(tmp_path):
    b = _bench()
    f = tmp_path / "perf.md"
    head, tail = "# title\n\ntext before\n", "\ntext after\n"
    f.write_text(f"{head}{b.BEGIN}\nold table\n{b.END}{tail}", encoding="utf-8")
    text = b.block([("a row", "1 s", "2 s", "<= 2 s")], "2026-12-02 06:00", "0.1, 0.2, 0.3", "0.4, 0.5, 0.6")
    b.splice(str(f), text)
    b.splice(str(f), text)  # again: the same file (idempotent)
    out = f.read_text(encoding="utf-8")
    assert out == f"{head}{b.BEGIN}\n{text}{b.END}{tail}"
    assert "| a row | 1 s | 2 s | <= 2 s |" in out and "load average (1, 5, 15 min) 0.1, 0.2, 0.3" in out
    assert "old table" not in out


@pytest.mark.parametrize("body", ["no markers\n", "<!-- bench_speed:end -->\n<!-- bench_speed:begin -->\n",
                                  "<!-- bench_speed:begin -->\n<!-- bench_speed:begin -->\n<!-- bench_speed:end -->\n"])
def test_splice_into_a_file_without_one_pair_of_markers_is_refused_before_measuring(tmp_path, capsys, body):
    b = _bench()
    f = tmp_path / "perf.md"
    f.write_text(body, encoding="utf-8")
    assert b.main(["--splice", str(f)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(f) in err[0] and "bench_speed:begin" in err[0]
    assert f.read_text(encoding="utf-8") == body
    assert b.main(["--splice", str(tmp_path / "missing.md")]) == 2
