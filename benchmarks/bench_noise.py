"""Generation speed and streaming memory of the IEEE-952 noise engine (sim/noise.py).

Run by hand: ``python benchmarks/bench_noise.py [--n-stream 1e8] [--skip-hdf5]``.
Prints (never asserts):

* the machine (nproc, CPU model, load average);
* a plain ``Generator.standard_normal`` baseline (float64, 1M per call) in the same run;
* the five-term model (Q, N, B, K, R) one-shot (``generate``, default settings) and
  streaming in 1M chunks (``stream().chunks``) with and without the draw thread, in
  samples/s of wall clock and per CPU-second, best of several repeats;
* the time per term (each term alone, streaming), to show where the time goes;
* the floor of any numpy generator of the five terms that changed the values to save draws: one
  uniform draw and its difference (Q), ONE Gaussian draw through one IIR filter for N and the
  full-rate flicker poles together (the flicker's sections and one more), and one linear
  interpolation from knots every 16 samples for everything slow (coarse flicker, K, R), each
  piece at its least numpy cost (the pieces only, not a generator);
* the peak resident memory (ru_maxrss of a fresh subprocess) while streaming 1e8
  samples of the five-term model to HDF5 with ``gyrobench.io.recording.HDF5StreamWriter``.
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time

import numpy as np

FS = 100.0
FIVE = dict(
    quantization=0.3,
    angle_random_walk=0.05,
    bias_instability=0.5,
    rate_random_walk=2.0,
    rate_ramp=1.0,
)


def machine() -> str:
    cpu = "unknown"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    load = os.getloadavg() if hasattr(os, "getloadavg") else ("?",)
    return (
        f"nproc={os.cpu_count()}  cpu={cpu!r}  python={platform.python_version()}  "
        f"numpy={np.__version__}  "
        f"loadavg={tuple(round(x, 2) for x in load)}"
    )


def best_rate(fn, n: int, repeats: int) -> tuple[float, float]:
    """Best-of-``repeats`` throughput [samples/s]: (wall clock, per CPU second of this process)."""
    best_wall = best_cpu = float("inf")
    for _ in range(repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        fn()
        best_wall = min(best_wall, time.perf_counter() - t0)
        best_cpu = min(best_cpu, time.process_time() - c0)
    return n / best_wall, n / best_cpu


def _line(label: str, rate: tuple[float, float], base: tuple[float, float] | None = None) -> None:
    wall, cpu = rate
    extra = f"  ({wall / base[0]:.2f} x baseline wall, {cpu / base[1]:.2f} x CPU)" if base else ""
    print(f"{label:50s}: {wall / 1e6:7.1f} M samples/s wall, {cpu / 1e6:7.1f} M per CPU-s{extra}")


def bench_speed(n: int, repeats: int) -> None:
    from gyrobench.sim import noise as nz
    from gyrobench.sim.noise import NoiseModel

    model = NoiseModel.from_datasheet(**FIVE)
    g = np.random.default_rng(0)
    buf = np.empty(1 << 20)

    def baseline():
        for _ in range(n >> 20):
            g.standard_normal(out=buf)

    base = best_rate(baseline, n, repeats)
    _line("standard_normal baseline (1M per call)", base)

    def one_shot():
        model.generate(n, FS, rng=np.random.default_rng(1))

    def streaming():
        s = model.stream(FS, rng=np.random.default_rng(1))
        for _ in s.chunks(n, 1 << 20):
            pass

    _line(f"five-term, one-shot generate({n:.1e})", best_rate(one_shot, n, repeats), base)
    nz._PREFETCH = True
    _line("five-term, streaming in 1M chunks, draw thread", best_rate(streaming, n, repeats), base)
    nz._PREFETCH = False
    _line("five-term, streaming, no draw thread", best_rate(streaming, n, repeats), base)
    print("per term alone (streaming in 1M chunks, no draw thread):")
    for name, v in FIVE.items():
        m = NoiseModel.from_datasheet(**{name: v})

        def one_term(m=m):
            s = m.stream(FS, rng=np.random.default_rng(1))
            for _ in s.chunks(n, 1 << 20):
                pass

        r = best_rate(one_term, n, repeats)
        print(
            f"    {name:18s}: {1e9 / r[1]:5.1f} ns per sample CPU"
            f" = {base[1] / r[1]:.2f} standard_normal draws"
        )
    nz._PREFETCH = "auto"
    t0 = time.perf_counter()
    model.stream(FS, rng=np.random.default_rng(1))
    print(
        f"stream construction (flicker factorisation, {len(model.flicker_poles(FS)[0])} poles): "
        f"{(time.perf_counter() - t0) * 1e3:.1f} ms"
    )


def bench_floor(n: int, repeats: int) -> None:
    from scipy import signal

    from gyrobench.sim.noise import NoiseModel

    blk = 1 << 16
    sos = NoiseModel.from_datasheet(**FIVE).stream(FS, rng=np.random.default_rng(1))._flicker.fine.sos
    sos = np.vstack([sos, [[1.0, 0.3, 0.0, 1.0, -0.5, 0.0]]])  # one more section: the white term's zero
    r_u, r_g = np.random.default_rng(1), np.random.default_rng(2)
    knots = np.random.default_rng(3).standard_normal(blk // 16 + 1)
    w = np.arange(16) / 16

    def floor() -> None:
        total, zi, prev = np.empty(n), np.zeros((sos.shape[0], 2)), 0.0
        for s in range(0, n, blk):
            acc = total[s : s + blk]
            e = r_u.random(blk)
            e *= 3.0
            acc[0] = e[0] - prev
            np.subtract(e[1:], e[:-1], out=acc[1:])
            prev = e[-1]
            y, zi = signal.sosfilt(sos, r_g.standard_normal(blk), zi=zi)
            acc += y
            c = np.multiply.outer(knots[1:] - knots[:-1], w)
            c += knots[:-1, None]
            acc += c.reshape(-1)

    g, buf = np.random.default_rng(0), np.empty(n)
    base = best_rate(lambda: g.standard_normal(out=buf), n, repeats)
    _line("floor of a one-Gaussian-draw generator (pieces)", best_rate(floor, n, repeats), base)


def hdf5_child(n: int, path: str) -> None:
    """Run in a fresh process: stream n samples to HDF5, print ru_maxrss."""
    from gyrobench.io.recording import HDF5StreamWriter
    from gyrobench.sim.noise import NoiseModel

    model = NoiseModel.from_datasheet(**FIVE)
    stream = model.stream(FS, rng=np.random.default_rng(2))
    t0 = time.perf_counter()
    with HDF5StreamWriter(path, name="noise", fs=FS, channels={"output": "rad/s"}) as w:
        for y in stream.chunks(n, 1 << 20):
            w.append(output=y)
    dt = time.perf_counter() - t0
    peak_kb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    print(f"{peak_kb} {dt} {os.path.getsize(path)}")


def bench_hdf5(n: int) -> None:
    with tempfile.TemporaryDirectory() as d:
        path = os.path.join(d, "noise.h5")
        out = subprocess.run(
            [sys.executable, __file__, "--hdf5-child", str(n), path],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.split()
        peak_kb, dt, size = int(out[0]), float(out[1]), int(out[2])
    print(
        f"stream {n:.0e} samples to HDF5 (1M chunks): peak RSS {peak_kb / 1024:.0f} MB, "
        f"{dt:.1f} s ({n / dt / 1e6:.1f} M samples/s incl. writing), file {size / 1e6:.0f} MB"
    )


def main() -> None:
    ap = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    ap.add_argument(
        "--n", type=float, default=2**25, help="samples per speed measurement (default 2^25)"
    )
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument(
        "--n-stream", type=float, default=1e8, help="samples streamed to HDF5 (default 1e8)"
    )
    ap.add_argument("--skip-hdf5", action="store_true")
    ap.add_argument("--hdf5-child", nargs=2, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.hdf5_child:
        hdf5_child(int(float(a.hdf5_child[0])), a.hdf5_child[1])
        return
    print(machine())
    n = int(a.n) >> 20 << 20
    bench_speed(n, a.repeats)
    bench_floor(n, a.repeats)
    if not a.skip_hdf5:
        bench_hdf5(int(a.n_stream))
    print(f"after: loadavg={tuple(round(x, 2) for x in os.getloadavg())}")


if __name__ == "__main__":
    main()
