"""Time to simulate a paper-000-like record with the reduced closed-loop FOG (run by hand).

Record: static 600 s, vibration 300 s (2 g: fixed 500 Hz sine, or a log sweep 1-500 Hz),
static 600 s, output 400 Hz, shaker at 3200 Hz (8 x the output rate: the rectified 2f of a
500 Hz tone stays below the physics Nyquist). Also the full-rate loop's cost per transit.

    .venv/bin/python benchmarks/bench_fog_loop.py
"""

from __future__ import annotations

import time

import numpy as np

from gyrobench.base import units
from gyrobench.sim.fog_loop import ClosedLoopFOG, LoopSpec, run_loop
from gyrobench.sim.noise import NoiseModel
from gyrobench.sim.sensor import Environment
from gyrobench.sim.shaker import FixedSine, Phased, SineSweep


def main() -> None:
    rng = np.random.default_rng(0)
    unit = ClosedLoopFOG(
        noise=NoiseModel.from_datasheet(bias_instability=0.003, rate_random_walk=0.0005, bias=0.05)
    )
    for label, vib in (
        ("fixed 500 Hz", FixedSine(frequency=500.0, duration=300.0, acceleration=units.g(2.0))),
        (
            "sweep 1-500 Hz",
            SineSweep(
                f_start=1.0, f_end=500.0, duration=300.0, acceleration=units.g(2.0), spacing="log"
            ),
        ),
    ):
        ph = Phased(vibration=vib, static_before=600.0, static_after=600.0)
        w0, c0 = time.perf_counter(), time.process_time()
        sh = ph.sample(3200.0, rng=rng)
        w1, c1 = time.perf_counter(), time.process_time()
        rec = unit.simulate(Environment(ph.duration, vibration=sh), fs=400.0, rng=rng)
        w2, c2 = time.perf_counter(), time.process_time()
        print(
            f"{label}: {rec.n_samples} samples; shaker {w1 - w0:.2f} s wall / {c1 - c0:.2f} s CPU; "
            f"FOG {w2 - w1:.2f} s wall / {c2 - c1:.2f} s CPU"
        )
    spec = LoopSpec()
    n = 1 << 20
    c0 = time.process_time()
    run_loop(spec, np.full(n, 1e-4), samples_per_output=512)
    print(f"full-rate loop: {(time.process_time() - c0) / n * 1e6:.2f} us CPU per transit")


if __name__ == "__main__":
    main()
