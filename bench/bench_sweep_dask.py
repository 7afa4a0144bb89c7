# SPDX-License-Identifier: MIT
"""Wall time of the paper's section 7 sweep (16 values of w10, t = 1) at a given net, by
bsdeform-run --sweep and by bsdeform.sweep on a local Dask cluster of 1 and 2 workers, and the
per-task overhead of a Dask sweep (docs/benchmarks.md, "Sweeps on Dask").

    PYTHONPATH=build/python BSDEFORM_RUN=build/ui/bsdeform-run \\
        python3 bench/bench_sweep_dask.py scenes/paper_sec7_central_square.iv --net 64
"""
import argparse
import os
import shutil
import subprocess
import tempfile
import time

import bsdeform
from bsdeform._sweep import find_program

VALUES = ["0", "0.0001", "0.001", "0.01", "0.1", "0.3", "0.5", "1", "2", "5", "7", "10", "25", "50", "75", "100"]


def timed(f):
    t = time.perf_counter()
    r = f()
    return time.perf_counter() - t, r


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene")
    ap.add_argument("--net", type=int, default=64)
    ap.add_argument("--until", default="1")
    ap.add_argument("--repeat", type=int, default=2, help="rounds; each figure is the best of them")
    a = ap.parse_args()
    run = find_program()
    sets = ["Surface.numUControlPoints=%d" % a.net, "Surface.numVControlPoints=%d" % a.net]
    set_args = [x for s in sets for x in ("--set", s)]
    fields = {"Surface.w10": VALUES}
    tmp = tempfile.mkdtemp()
    from distributed import Client, LocalCluster
    figures = {}

    def note(name, seconds):
        figures.setdefault(name, []).append(seconds)

    try:
        # The rounds interleave the ways (the machine is shared: a busy moment then hits them all).
        for i in range(a.repeat):
            note("one run", timed(lambda: subprocess.run([run, a.scene, "--until", a.until, "--set", "Surface.w10=1",
                                                          *set_args, "--result-only"], check=True, capture_output=True))[0])
            note("0 steps", timed(lambda: subprocess.run([run, a.scene, "--steps", "0", *set_args, "--result-only"],
                                                         check=True, capture_output=True))[0])
            out = os.path.join(tmp, "runner%d" % i)
            note("bsdeform-run --sweep", timed(lambda: subprocess.run(
                [run, a.scene, "--until", a.until, *set_args, "--sweep", "Surface.w10=" + ",".join(VALUES), "-o", out,
                 "--quiet"], check=True))[0])
            reference = open(os.path.join(out, "sweep.csv"), "rb").read()
            for workers in (1, 2):
                out = os.path.join(tmp, "dask%d_%d" % (workers, i))
                t, _ = timed(lambda: bsdeform.sweep(a.scene, fields, until=float(a.until), sets=sets, workers=workers,
                                                    out=out, progress=False))
                assert open(os.path.join(out, "sweep.csv"), "rb").read() == reference, "not bsdeform-run's sweep.csv"
                note("dask %d, whole" % workers, t)
                t, cluster = timed(lambda: LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                                        dashboard_address=None))
                note("dask %d, cluster start" % workers, t)
                client = Client(cluster)
                try:
                    t, r = timed(lambda: bsdeform.sweep(a.scene, fields, until=float(a.until), sets=sets,
                                                        client=client, progress=False))
                    note("dask %d, running cluster" % workers, t)
                    if workers == 1:
                        # the same sweep's own run times: what is left is Dask's and the task's share
                        inside = sum(x.seconds for x in r)
                        note("bsdeform-run inside a task", inside / len(r))
                        note("per task beyond bsdeform-run", (t - inside) / len(r))
                        t0 = time.perf_counter()
                        client.gather(client.map(abs, range(-1000 * (i + 1), -1000 * i)))
                        note("trivial task", (time.perf_counter() - t0) / 1000)
                finally:
                    client.close()
                    cluster.close()
        print("net %d, until %s, %d values, best of %d; load average now %s" % (
            a.net, a.until, len(VALUES), a.repeat, open("/proc/loadavg").read().split()[0]))
        for name, xs in figures.items():
            print("  %-32s %8.3f s   (all: %s)" % (name, min(xs), " ".join("%.3f" % x for x in xs)))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
