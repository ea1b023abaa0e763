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


_ROWS = [
    ("p000_fog_vibration unit (median of seeds 1-3; max peak)", "1.55 s CPU, 313 MB peak", "-", "<= 2 s CPU"),
    ("five-term noise (Q, N, B, K, R), one-shot, 4.2 M samples (best of repeats)", "17.4 M samples per CPU-s",
     "standard_normal 97.2 M per CPU-s: **0.18x**", ">= 0.5x"),
    ("floor of an exact per-term generator: its draws alone (3 standard_normal + 1 random a sample)",
     "32.2 M samples per CPU-s", "**0.31x**", "(>= 0.5x unreachable)"),
    ("ADEV + fit, 2e+05 samples, in process (median of 7)", "12.8 ms CPU", "allantools + NNLS 26.3 ms: **2.06x**",
     ">= 1.5x"),
    ("ADEV + fit, 1e8 samples, fresh process, one pair (peak RSS of the process)", "3.5 s CPU, 956 MB",
     "21.7 s, 3159 MB: **6.20x**", ">= 8x CPU, <= 1 GB"),
    ("`gyrobench reproduce --all`", "200 s CPU (112 s wall), store 8.5 MB", "-", "< 5 min loaded, < 20 MB"),
    ("`gyrobench reproduce --all`, the other core busy (a spinning process beside it)", "190 s wall", "-", "< 5 min"),
]


def test_the_readme_summary_is_made_from_the_spliced_block(tmp_path, capsys):
    """Rows spliced into a performance page read back unchanged, and the README paragraph made from
    them (``--summary R --from P``, measuring nothing) carries each figure, the date and the load."""
    b = _bench()
    perf, readme = tmp_path / "perf.md", tmp_path / "README.md"
    perf.write_text(f"# perf\n{b.BEGIN}\n{b.END}\n", encoding="utf-8")
    readme.write_text(f"intro\n\n{b.SUMMARY_BEGIN}\nold\n{b.SUMMARY_END}\n\nrest\n", encoding="utf-8")
    b.splice(str(perf), b.block(_ROWS, "2026-12-04 01:33", "0.1, 0.1, 0.1", "1.7, 0.9, 0.4"))
    heading, rows = b.read_block(str(perf))
    assert rows == _ROWS and heading.startswith("Measured 2026-12-04 01:33 UTC")
    assert b.main(["--summary", str(readme), "--from", str(perf)]) == 0
    text = readme.read_text(encoding="utf-8")
    assert text.startswith("intro\n\n") and text.endswith("\n\nrest\n") and "old" not in text
    assert max(len(line) for line in text.splitlines()) <= 100  # wrapped like the README's prose
    words = " ".join(text.split())
    for figure in ("2026-12-04 01:33 UTC", "load 0.1", "1.55 s for paper 000 (313 MB peak)", "0.18x", "0.31x",
                   "2.06x as fast as allantools + NNLS at 2e5 samples", "6.20x at 1e8 (956 MB against 3159 MB)",
                   "takes 112 s and stores 8.5 MB", "other core busy it takes 190 s wall"):
        assert figure in words, figure


def test_summary_options_are_refused_in_one_line_before_measuring(tmp_path, capsys):
    b = _bench()
    perf, readme = tmp_path / "perf.md", tmp_path / "README.md"
    perf.write_text(f"{b.BEGIN}\n{b.END}\n", encoding="utf-8")
    readme.write_text("no markers\n", encoding="utf-8")
    assert b.main(["--summary", str(readme), "--from", str(perf)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and str(readme) in err[0] and "summary:begin" in err[0]
    assert b.main(["--from", str(perf)]) == 2  # --from measures nothing, so it needs --summary
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--summary" in err[0]
    assert readme.read_text(encoding="utf-8") == "no markers\n"


def test_a_block_whose_figures_cannot_be_read_is_refused_not_summarised_with_gaps(tmp_path, capsys):
    """A row whose cell lost its figure (say, a hand edit) stops the summary in one line naming the cell."""
    b = _bench()
    perf, readme = tmp_path / "perf.md", tmp_path / "README.md"
    perf.write_text(f"{b.BEGIN}\n{b.END}\n", encoding="utf-8")
    readme.write_text(f"{b.SUMMARY_BEGIN}\nold\n{b.SUMMARY_END}\n", encoding="utf-8")
    rows = [(r[0], "n/a", r[2], r[3]) if r[0].startswith("p000") else r for r in _ROWS]
    b.splice(str(perf), b.block(rows, "2026-12-04 01:33", "0.1, 0.1, 0.1", "1.7, 0.9, 0.4"))
    assert b.main(["--summary", str(readme), "--from", str(perf)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "'n/a'" in err[0]
    assert "old" in readme.read_text(encoding="utf-8")
