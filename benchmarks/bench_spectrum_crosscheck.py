"""Cost of the spectrum cross-check (the shipped study: the default column, coarse mesh).

* the FEM cost of one grid point (mean over the grid: its share of the batched kernel's time),
  and the wall time of the shipped 30-point grid on the local cores (the points of a worker
  advance together, 8 pulses per pass through the stiffness; issue 19's target: 40 s on 2);
* with --fine, a 16 x 16 grid of the same study on the local cores (target: 5 minutes on 2);
* the Dask path on a LocalCluster with 1 and 2 single-threaded workers over the same 4 points:
  the measured speed-up gives a parallel efficiency, and from it what a 64-core cluster would
  take for the shipped grid and for a 16 x 16 one.

Run: make bench (takes a few minutes; --fine adds about ten). Each run writes into a fresh
temporary directory.
"""

from __future__ import annotations

import json
import os
import sys
import tempfile
import time
from pathlib import Path

from colonna.studies.cli import resolve_study
from colonna.studies.spectrum_crosscheck import run as run_spectrum_crosscheck


def timed(study, out, **kwargs) -> tuple[float, dict]:
    start = time.perf_counter()
    summary = run_spectrum_crosscheck(study, out, progress=False, **kwargs)
    return time.perf_counter() - start, summary


def main() -> None:
    study = resolve_study("spectrum-crosscheck")
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        timed(study, tmp / "warm", grid=(1, 1), workers=1)  # numba caches
        wall, full = timed(study, tmp / "full", workers=cores)
        per_point = full["fem_seconds_per_point"]
        points = full["points"]
        print(f"cores: {cores}")
        print(
            f"FEM cost per grid point: {per_point:.1f} s (mean of {points}; the rigid models "
            "add a few ms)"
        )
        print(f"shipped grid ({points} points) on {cores} local processes: {wall:.0f} s")
        settled = sum(
            json.loads(p.read_text())["status_fem"].startswith("settled")
            for p in (tmp / "full" / "cases").glob("*/result.json")
        )
        print(f"  {settled} of its points stopped once settled (could no longer overturn)")
        if "--fine" in sys.argv:
            fine_wall, fine = timed(study, tmp / "fine", grid=(16, 16), workers=cores)
            print(
                f"16 x 16 grid ({fine['points']} points) on {cores} local processes: "
                f"{fine_wall:.0f} s ({fine['fem_seconds_per_point']:.1f} s of FEM per point)"
            )
        from distributed import Client, LocalCluster

        times = {}
        for n in (1, 2):
            with (
                LocalCluster(
                    n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None
                ) as cluster,
                Client(cluster),
            ):
                times[n], _ = timed(
                    study, tmp / f"dask{n}", grid=(2, 2), scheduler=cluster.scheduler_address
                )
        speedup = times[1] / times[2]
        efficiency = speedup / 2.0
        print(
            f"Dask, 4 points: 1 worker {times[1]:.1f} s, 2 workers {times[2]:.1f} s: speed-up "
            f"{speedup:.2f}, efficiency {efficiency:.2f}"
        )
        serial = per_point * points
        longest = max(
            json.loads(p.read_text())["fem_seconds"]
            for p in (tmp / "full" / "cases").glob("*/result.json")
        )
        t64 = max(longest, serial / (64 * efficiency))
        print(
            f"64 cores, shipped grid: about {t64:.0f} s (its {points} points are fewer than "
            f"the cores: the longest point, {longest:.0f} s, bounds it)"
        )
        n16 = 256
        print(
            f"64 cores, a 16 x 16 grid: about {n16 * per_point / (64 * efficiency):.0f} s "
            f"({n16} points x {per_point:.1f} s / (64 x {efficiency:.2f}))"
        )


if __name__ == "__main__":
    main()
