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
import statistics
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
    ap.add_argument("--repeat", type=int, default=2, help="best of N for each figure")
    a = ap.parse_args()
    run = find_program()
    sets = ["Surface.numUControlPoints=%d" % a.net, "Surface.numVControlPoints=%d" % a.net]
    set_args = [x for s in sets for x in ("--set", s)]
    tmp = tempfile.mkdtemp()
    best = lambda xs: min(xs)  # noqa: E731
    try:
        # one run, and a run of 0 steps (process start, scene read, model build), by themselves
        one = [timed(lambda: subprocess.run([run, a.scene, "--until", a.until, "--set", "Surface.w10=1", *set_args,
                                             "--result-only"], check=True, capture_output=True))[0]
               for _ in range(a.repeat)]
        zero = [timed(lambda: subprocess.run([run, a.scene, "--steps", "0", *set_args, "--result-only"], check=True,
                                             capture_output=True))[0] for _ in range(max(3, a.repeat))]
        runner = []
        for i in range(a.repeat):
            out = os.path.join(tmp, "runner%d" % i)
            runner.append(timed(lambda: subprocess.run([run, a.scene, "--until", a.until, *set_args, "--sweep",
                                                        "Surface.w10=" + ",".join(VALUES), "-o", out, "--quiet"],
                                                       check=True))[0])
        reference = open(os.path.join(tmp, "runner0", "sweep.csv"), "rb").read()
        print("one run %.2f s, a run of 0 steps %.3f s (median %.3f)" % (best(one), best(zero), statistics.median(zero)))
        print("bsdeform-run --sweep: %.2f s" % best(runner))

        from distributed import Client, LocalCluster
        for workers in (1, 2):
            whole = []
            for i in range(a.repeat):
                out = os.path.join(tmp, "dask%d_%d" % (workers, i))
                t, r = timed(lambda: bsdeform.sweep(a.scene, {"Surface.w10": VALUES}, until=float(a.until), sets=sets,
                                                    workers=workers, out=out, progress=False))
                assert open(os.path.join(out, "sweep.csv"), "rb").read() == reference, "not bsdeform-run's sweep.csv"
                whole.append(t)
            start, cluster = timed(lambda: LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                                        dashboard_address=None))
            client = Client(cluster)
            try:
                warm = [timed(lambda: bsdeform.sweep(a.scene, {"Surface.w10": VALUES}, until=float(a.until), sets=sets,
                                                     client=client, progress=False))[0] for _ in range(a.repeat)]
                # a task that does nothing: the scheduler's round trip per task
                trivial = []
                for _ in range(3):
                    t0 = time.perf_counter()
                    client.gather(client.map(abs, range(-1000 * (len(trivial) + 1), -1000 * len(trivial))))
                    trivial.append((time.perf_counter() - t0) / 1000)
            finally:
                client.close()
                cluster.close()
            print("bsdeform.sweep, %d local worker(s): %.2f s with the cluster's start (%.2f s of it), %.2f s on a "
                  "running cluster" % (workers, best(whole), start, best(warm)))
            if workers == 1:
                per_task = (best(warm) - len(VALUES) * best(one)) / len(VALUES)
                print("  per task beyond the run itself (1 worker, running cluster): %.3f s; a trivial task's round "
                      "trip %.2f ms" % (per_task, 1000 * best(trivial)))
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    main()
