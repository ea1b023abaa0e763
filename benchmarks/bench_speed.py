"""Every speed target of the project side by side with its peer, in one run, as one markdown table.

Run by hand: ``python benchmarks/bench_speed.py [--units 3] [--repeat 7] [--big] [--reproduce]``.
Prints (never asserts) the date, the machine and its load average (before and after), then a
table of CPU times (``time.process_time`` of the process doing the work, all its threads; on a
shared machine wall time includes waiting for a core, CPU time does not, though a loaded machine
still slows CPU work through shared caches and memory bandwidth):

* each paper's unit (``experiment(Config(), seed)``, seeds 1..``--units``, each in a fresh
  subprocess with one BLAS thread and ``units.keep_freed_memory``, as the runner's workers):
  median CPU and peak RSS increase
  (``ru_maxrss`` minus the RSS after the imports); target <= 2 s CPU;
* the five-term noise record (Q, N, B, K, R of ``bench_noise.py``, one-shot ``generate``,
  draw thread off) against ``Generator.standard_normal`` of as many float64 samples: CPU rate
  and ratio; target >= 0.5x; the same in wall time with the draw thread on (the default); and the
  floor of any exact per-term generator, its draws alone (three Gaussian draws, for N, B and K,
  and one uniform, for Q, per sample);
* the overlapping ADEV (octave taus) + IEEE fit against ``allantools.oadev`` + the NNLS fit of
  ``bench_allan.py`` at 2e5 and 1e6 samples: in process (median of ``--repeat`` warm calls) and
  the first call of a fresh process (``--first`` pairs of fresh processes, ours then the peer's
  back to back, the median of the pairs' ratios); 1e8 with ``--big`` (fresh processes, peak RSS; needs ~4 GB
  free); targets >= 1.5x (2e5, 1e6), >= 8x CPU at <= 1 GB (1e8);
* the unit store: each paper's unit as stored (codec JSON, zlib; whole and slim) and what
  ``reproduce --all`` stores (20 units whole or slim by the scenario's ``REPORT_UNITS`` and 20
  control units slim, from those sizes); ``--reproduce`` runs ``gyrobench reproduce --all`` in a
  temporary folder and reports its CPU (``RUSAGE_CHILDREN``) and the store's size; target < 20 MB;
  ``--busy`` runs it again beside a process spinning on one core and reports its wall time
  (target < 5 min).

``--summary FILE`` writes the README's one-paragraph summary of the same rows between
``<!-- bench_speed:summary:begin -->`` and ``<!-- bench_speed:summary:end -->``; with
``--from PERF.md`` it takes the rows of the block already spliced there and measures nothing.

``--splice FILE`` also writes the block (date, machine, load, table) into FILE between the lines
``<!-- bench_speed:begin -->`` and ``<!-- bench_speed:end -->`` (docs/performance.md holds them),
replacing what was there; the rest of FILE is kept byte for byte and the file is replaced
atomically. A FILE without exactly one pair of markers is refused in one line (exit 2) before
anything is measured.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
PAPERS = ("p000_fog_vibration", "p001_mems_scale_factor", "p003_ifog_thermal", "p004_rlg_thermal")
FS = 100.0

_UNIT = """
import importlib, json, resource, sys, time
import numpy, scipy.signal, scipy.optimize, sklearn.neural_network
from threadpoolctl import threadpool_limits
from gyrobench.scenarios.runner import units
units.keep_freed_memory()  # as the runner's workers run a unit
mod = importlib.import_module("gyrobench.scenarios.papers." + sys.argv[1])
cfg = mod.Config()
rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
with threadpool_limits(limits=1):
    c = time.process_time()
    mod.experiment(cfg, int(sys.argv[2]))
    cpu = time.process_time() - c
print(json.dumps({"cpu": cpu, "peak_mb": (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0) / 1024}))
"""

_FIRST = """
import json, sys, time, resource
import numpy as np
sys.path.insert(0, sys.argv[3])
import allantools, scipy.optimize, scipy.stats
from bench_allan import nnls_fit
from gyrobench.analysis.allan import allan_deviation, fit_noise
y = np.load(sys.argv[2])
m = 2 ** np.arange(int(np.log2(y.size // 4)) + 1)
rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
c = time.process_time()
if sys.argv[1] == "gyrobench":
    fit_noise(allan_deviation(y, 100.0))
else:
    t, d, _, _ = allantools.oadev(y, rate=100.0, data_type="freq", taus=m / 100.0)
    nnls_fit(np.asarray(t), np.asarray(d) ** 2)
cpu = time.process_time() - c
print(json.dumps({"cpu": cpu, "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}))
"""


def load() -> str:
    return ", ".join(f"{x:.1f}" for x in os.getloadavg())


def _json_run(args: list[str]) -> dict:
    out = subprocess.run([sys.executable, *args], check=True, capture_output=True, text=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def units(n_units: int) -> list[tuple[str, str, str, str]]:
    rows = []
    for name in PAPERS:
        runs = [_json_run(["-c", _UNIT, name, str(s)]) for s in range(1, n_units + 1)]
        cpu = statistics.median(r["cpu"] for r in runs)
        peak = max(r["peak_mb"] for r in runs)
        rows.append((f"{name} unit (median of seeds 1-{n_units}; max peak)", f"{cpu:.2f} s CPU, {peak:.0f} MB peak",
                     "-", "<= 2 s CPU"))
    return rows


def noise(repeat: int) -> list[tuple[str, str, str, str]]:
    from bench_noise import FIVE

    from gyrobench.sim import noise as nz
    from gyrobench.sim.noise import NoiseModel

    nz._PREFETCH = False
    n = 1 << 22
    model = NoiseModel.from_datasheet(**FIVE)
    g = np.random.default_rng(0)
    out = np.empty(n)

    def best(fn, clock=time.process_time) -> float:
        t = []
        for _ in range(repeat):
            c = clock()
            fn()
            t.append(clock() - c)
        return min(t)

    def wall(fn) -> float:
        return best(fn, time.perf_counter)

    base = best(lambda: g.standard_normal(n, out=out))
    ours = best(lambda: model.generate(n, FS, rng=np.random.default_rng(1)))
    # the floor of any exact per-term generator: N, B and K each need n Gaussian draws of their
    # own (full-rank covariances, independent streams) and Q n uniform ones, before any filtering
    u = np.empty(n)
    floor = best(lambda: (g.standard_normal(n, out=out), g.standard_normal(n, out=out),
                          g.standard_normal(n, out=out), g.random(n, out=u)))
    nz._PREFETCH = True
    base_w = wall(lambda: g.standard_normal(n, out=out))
    ours_w = wall(lambda: model.generate(n, FS, rng=np.random.default_rng(1)))
    nz._PREFETCH = False
    return [("five-term noise (Q, N, B, K, R), one-shot, 4.2 M samples (best of repeats)",
             f"{n / ours / 1e6:.1f} M samples per CPU-s", f"standard_normal {n / base / 1e6:.1f} M per CPU-s: "
             f"**{base / ours:.2f}x**", ">= 0.5x"),
            ("five-term noise, wall time with the worker thread on (the default when a core is idle), 2 cores",
             f"{n / ours_w / 1e6:.1f} M samples per s", f"standard_normal {n / base_w / 1e6:.1f} M per s: "
             f"**{base_w / ours_w:.2f}x**", "-"),
            ("floor of an exact per-term generator: its draws alone (3 standard_normal + 1 random a sample)",
             f"{n / floor / 1e6:.1f} M samples per CPU-s", f"**{base / floor:.2f}x**", "(>= 0.5x unreachable)")]


def _data(n: int, folder: str) -> str:
    from coverage_fit import model

    path = os.path.join(folder, f"allan_{n}.npy")
    if not os.path.exists(path):
        out = np.lib.format.open_memmap(path, mode="w+", dtype=np.float64, shape=(n,))
        stream = model().stream(FS, rng=np.random.default_rng(20261121))
        for a in range(0, n, 1 << 22):
            b = min(n, a + (1 << 22))
            out[a:b] = stream.take(b - a)
        out.flush()
        del out
    return path


def allan(sizes: list[int], repeat: int, folder: str, big: bool, first: int = 7) -> list[tuple[str, str, str, str]]:
    import allantools
    from bench_allan import nnls_fit

    from gyrobench.analysis.allan import allan_deviation, fit_noise

    rows = []
    for n in sizes:
        path = _data(n, folder)
        y = np.load(path)
        m = 2 ** np.arange(int(np.log2(y.size // 4)) + 1)

        def ours(y=y) -> None:
            fit_noise(allan_deviation(y, FS))

        def peer(y=y, m=m) -> None:
            t, d, _, _ = allantools.oadev(y, rate=FS, data_type="freq", taus=m / FS)
            nnls_fit(np.asarray(t), np.asarray(d) ** 2)

        ours()
        peer()
        tg, tp = [], []
        for i in range(repeat):
            yy = y if i % 2 == 0 else y[::-1].copy()  # other data, same n: no per-record cache helps
            for fn, acc in ((ours, tg), (peer, tp)):
                c = time.process_time()
                fn(yy)
                acc.append(time.process_time() - c)
        g, p = statistics.median(tg), statistics.median(tp)
        rows.append((f"ADEV + fit, {n:.0e} samples, in process (median of {repeat})",
                     f"{g * 1e3:.1f} ms CPU", f"allantools + NNLS {p * 1e3:.1f} ms: **{p / g:.2f}x**", ">= 1.5x"))
        # paired: each pair's two fresh processes run back to back, so a change of the machine's
        # load between pairs moves both; the ratio is the median of the pairs' ratios
        pairs = [(_json_run(["-c", _FIRST, "gyrobench", path, HERE])["cpu"],
                  _json_run(["-c", _FIRST, "allantools", path, HERE])["cpu"]) for _ in range(first)]
        g, p = statistics.median(a for a, _ in pairs), statistics.median(b for _, b in pairs)
        ratio = statistics.median(b / a for a, b in pairs)
        rows.append((f"ADEV + fit, {n:.0e} samples, first call of a fresh process (median of {first} pairs)",
                     f"{g * 1e3:.1f} ms CPU", f"{p * 1e3:.1f} ms: **{ratio:.2f}x** (median pair ratio)", ">= 1.5x"))
    if big:
        n = 100_000_000
        path = _data(n, folder)
        g = _json_run(["-c", _FIRST, "gyrobench", path, HERE])
        p = _json_run(["-c", _FIRST, "allantools", path, HERE])
        rows.append(("ADEV + fit, 1e8 samples, fresh process, one pair (peak RSS of the process)",
                     f"{g['cpu']:.1f} s CPU, {g['peak_mb']:.0f} MB", f"{p['cpu']:.1f} s, {p['peak_mb']:.0f} MB: "
                     f"**{p['cpu'] / g['cpu']:.2f}x**", ">= 8x CPU, <= 1 GB"))
    return rows


def store(reproduce: bool, folder: str, busy: bool = False) -> list[tuple[str, str, str, str]]:
    import importlib

    from threadpoolctl import threadpool_limits

    from gyrobench.scenarios.runner import codec
    from gyrobench.scenarios.runner import units as runner

    rows, total = [], 0.0
    for name in PAPERS:
        mod = importlib.import_module(f"gyrobench.scenarios.papers.{name}")
        with threadpool_limits(limits=1):
            r = mod.experiment(mod.Config(), 1)
        plain = len(codec.dumps(r))
        whole = len(codec.dumps_compressed(r))
        slim = len(codec.dumps_compressed(runner.slim_result(mod, r)))
        k = min(20, getattr(mod, "REPORT_UNITS", 20))
        total += k * whole + (20 - k) * slim + 20 * slim
        rows.append((f"{name}: one unit as stored", f"{whole / 1e3:.0f} kB whole, {slim / 1e3:.0f} kB slim",
                     f"{plain / 1e3:.0f} kB as the previous format's JSON", "-"))
    rows.append(("unit store of `reproduce --all` (20 + 20 control units a paper, from the sizes above)",
                 f"{total / 1e6:.1f} MB", "166 MB before", "< 20 MB"))
    if reproduce:
        out = os.path.join(folder, "rep")
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        wall = _reproduce_all(out)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime
        size = os.path.getsize(out + ".units.sqlite")
        rows.append(("`gyrobench reproduce --all`", f"{cpu:.0f} s CPU ({wall:.0f} s wall), store {size / 1e6:.1f} MB",
                     "-", "< 5 min loaded, < 20 MB"))
    if busy:
        rows.append(reproduce_busy(folder))
    return rows


_CLI = "import sys; from gyrobench.scenarios.cli.main import main; sys.exit(main(sys.argv[1:]))"


def _reproduce_all(out: str) -> float:
    """Wall seconds of ``gyrobench reproduce --all --out OUT -q`` in a subprocess."""
    t0 = time.perf_counter()
    subprocess.run([sys.executable, "-c", _CLI, "reproduce", "--all", "--out", out, "-q"],
                   check=True, capture_output=True)
    return time.perf_counter() - t0


def reproduce_busy(folder: str) -> tuple[str, str, str, str]:
    """``reproduce --all`` into a fresh folder while a spinning process keeps one core busy (wall time)."""
    spin = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        time.sleep(2.0)  # let the spinner take its core
        wall = _reproduce_all(os.path.join(folder, "rep_busy"))
    finally:
        spin.kill()
        spin.wait()
    return ("`gyrobench reproduce --all`, the other core busy (a spinning process beside it)",
            f"{wall:.0f} s wall", "-", "< 5 min")


BEGIN, END = "<!-- bench_speed:begin -->", "<!-- bench_speed:end -->"
SUMMARY_BEGIN, SUMMARY_END = "<!-- bench_speed:summary:begin -->", "<!-- bench_speed:summary:end -->"


def _marker_span(text: str, path: str, begin: str = BEGIN, end: str = END) -> tuple[int, int]:
    """(start, end) of what lies between the markers of ``text``; ValueError naming ``path`` otherwise."""
    if text.count(begin) != 1 or text.count(end) != 1 or text.index(begin) > text.index(end):
        raise ValueError(f"{path}: needs exactly one line {begin!r} followed by one line {end!r}")
    return text.index(begin) + len(begin), text.index(end)


def splice(path: str, block: str, begin: str = BEGIN, end: str = END) -> None:
    """Replace what lies between the markers of ``path`` by ``block`` (atomic: temporary file, rename)."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    a, b = _marker_span(text, path, begin, end)
    tmp = f"{path}.bench_speed.tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text[:a] + "\n" + block.strip("\n") + "\n" + text[b:])
    os.replace(tmp, path)


def block(rows: list[tuple[str, str, str, str]], started: str, load0: str, load1: str) -> str:
    """The markdown block: date and machine, the load at the start and the end, the table."""
    import numpy

    lines = [f"Measured {started} UTC by `python benchmarks/bench_speed.py`: nproc={os.cpu_count()}, "
             f"python {platform.python_version()}, numpy {numpy.__version__}; load average (1, 5, 15 min) "
             f"{load0} at the start, {load1} at the end. CPU seconds of the process doing the work (a "
             f"loaded machine still slows them through shared caches and memory bandwidth).", "",
             "| what | gyrobench | peer (same run) | target |", "|---|---|---|---|"]
    lines += ["| " + " | ".join(r) + " |" for r in rows]
    return "\n".join(lines) + "\n"


def read_block(path: str) -> tuple[str, list[tuple[str, str, str, str]]]:
    """The first line (date, machine, load) and the table rows of the block spliced into ``path``."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    a, b = _marker_span(text, path)
    lines = [ln for ln in text[a:b].strip().splitlines() if ln.strip()]
    rows = []
    for ln in lines[3:]:  # after the heading line, the table header and its rule
        cells = [c.strip() for c in ln.strip().strip("|").split(" | ")]
        if len(cells) != 4:
            raise ValueError(f"{path}: a table row of the block does not have 4 cells: {ln!r}")
        rows.append((cells[0], cells[1], cells[2], cells[3]))
    return lines[0], rows


def summary(heading: str, rows: list[tuple[str, str, str, str]]) -> str:
    """The README's speed paragraph, from the rows of one run and its heading line (date, load)."""
    import re
    import textwrap

    def find(prefix: str) -> tuple[str, str, str, str] | None:
        return next((r for r in rows if r[0].startswith(prefix)), None)

    def grab(pattern: str, cell: str) -> tuple[str, ...]:
        m = re.search(pattern, cell)
        if m is None:
            raise ValueError(f"the block's cell {cell!r} does not hold the figure the summary needs ({pattern})")
        return m.groups()

    def ratio(cell: str) -> str:
        return grab(r"\*\*([0-9.]+x)\*\*", cell)[0]

    (date,) = grab(r"Measured (\S+ \S+ UTC)", heading)
    (load,) = grab(r"load average \(1, 5, 15 min\) ([0-9.]+), [0-9.]+, [0-9.]+ at the start", heading)
    parts = []
    units = []
    for name in PAPERS:
        r = find(f"{name} unit")
        if r is not None:
            cpu, peak = grab(r"([0-9.]+) s CPU, ([0-9]+) MB", r[1])
            units.append(f"{cpu} s for {name[1:4]} ({peak} MB peak)")
    if units:
        parts.append("one unit of a paper costs " + units[0].replace(" for ", " for paper ", 1)
                     + "".join(", " + u for u in units[1:]))
    adev = []
    for n in ("2e+05", "1e+06"):
        r = find(f"ADEV + fit, {n} samples, in process")
        if r is not None:
            adev.append(f"{ratio(r[2])} at {n.replace('+0', '')}")
    big = find("ADEV + fit, 1e8")
    if big is not None:
        (ours_mb,), (peer_mb,) = grab(r"([0-9]+) MB", big[1]), grab(r"([0-9]+) MB", big[2])
        adev.append(f"{ratio(big[2])} at 1e8 ({ours_mb} MB against {peer_mb} MB)")
    if adev:
        parts.append("Allan deviation + fit runs " + adev[0].replace(" at ", " as fast as allantools + NNLS at ", 1)
                     + " samples" + "".join(", " + a for a in adev[1:]))
    noise, floor = find("five-term noise (Q"), find("floor of an exact per-term")
    if noise is not None:
        text = f"five-term noise is generated at {ratio(noise[2])} numpy's `standard_normal` rate"
        if floor is not None:
            text += f" (the draws of any exact per-term generator alone cap it at {ratio(floor[2])})"
        parts.append(text)
    loaded, plain = find("`gyrobench reproduce --all`,"), find("`gyrobench reproduce --all`")
    if plain is not None and plain is not loaded:
        wall, size = grab(r"\(([0-9]+) s wall\), store ([0-9.]+) MB", plain[1])
        parts.append(f"`reproduce --all` takes {wall} s and stores {size} MB of units")
    if loaded is not None:
        parts.append(f"with the machine's other core busy it takes {loaded[1]}")
    when = f"{date}, 2 cores, load {load} at the start"
    text = (f"**Speed** (generated by `benchmarks/bench_speed.py`, {when}; CPU time; "
            f"[docs/performance.md](docs/performance.md)): " + "; ".join(parts) + ".")
    return textwrap.fill(text, width=100, break_on_hyphens=False, break_long_words=False)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--units", type=int, default=3, help="seeds per paper's unit (default 3)")
    ap.add_argument("--repeat", type=int, default=7, help="repeats of the in-process timings (default 7)")
    ap.add_argument("--sizes", default="200000,1000000", help="record lengths of the Allan rows")
    ap.add_argument("--first", type=int, default=7, help="pairs of fresh processes of the first-call rows (default 7)")
    ap.add_argument("--big", action="store_true", help="also 1e8 samples (800 MB of data, ~4 GB peak for the peer)")
    ap.add_argument("--reproduce", action="store_true", help="also run `gyrobench reproduce --all` (minutes)")
    ap.add_argument("--busy", action="store_true",
                    help="also run `gyrobench reproduce --all` beside a process spinning on one core (minutes)")
    ap.add_argument("--data-dir", default=None, help="where the Allan records are kept (default a temporary folder)")
    ap.add_argument("--splice", metavar="FILE", default=None,
                    help=f"also write the table into FILE between the lines {BEGIN} and {END}")
    ap.add_argument("--summary", metavar="FILE", default=None,
                    help=f"also write the README's speed paragraph into FILE between {SUMMARY_BEGIN} and {SUMMARY_END}")
    ap.add_argument("--from", dest="from_", metavar="FILE", default=None,
                    help="with --summary: take the rows from the block already spliced into FILE (measure nothing)")
    args = ap.parse_args(argv)
    for opt, path, markers in (("--splice", args.splice, (BEGIN, END)),
                               ("--summary", args.summary, (SUMMARY_BEGIN, SUMMARY_END)),
                               ("--from", args.from_, (BEGIN, END))):
        if path is not None:
            try:
                with open(path, encoding="utf-8") as f:
                    _marker_span(f.read(), path, *markers)
            except (OSError, ValueError) as exc:
                print(f"bench_speed: {opt} {exc}", file=sys.stderr)
                return 2
    if args.from_ is not None:
        if args.summary is None:
            print("bench_speed: --from needs --summary FILE (it measures nothing)", file=sys.stderr)
            return 2
        try:
            text = summary(*read_block(args.from_))
        except ValueError as exc:
            print(f"bench_speed: --from {exc}", file=sys.stderr)
            return 2
        splice(args.summary, text, SUMMARY_BEGIN, SUMMARY_END)
        print(f"summary of {args.from_} spliced into {args.summary}")
        return 0
    load0 = load()
    started = f"{datetime.datetime.now(datetime.timezone.utc):%Y-%m-%d %H:%M}"
    print(f"# gyrobench speed, {started} UTC")
    with tempfile.TemporaryDirectory() as tmp:
        folder = args.data_dir or tmp
        rows = units(args.units)
        rows += noise(args.repeat)
        rows += allan([int(float(s)) for s in args.sizes.split(",")], args.repeat, folder, args.big, args.first)
        rows += store(args.reproduce, tmp, args.busy)
    text = block(rows, started, load0, load())
    print(text)
    if args.splice is not None:
        splice(args.splice, text)
        print(f"spliced into {args.splice}")
    if args.summary is not None:
        splice(args.summary, summary(text.splitlines()[0], rows), SUMMARY_BEGIN, SUMMARY_END)
        print(f"summary spliced into {args.summary}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
