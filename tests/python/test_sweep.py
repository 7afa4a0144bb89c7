# SPDX-License-Identifier: MIT
"""bsdeform.sweep and `python3 -m bsdeform sweep` on Dask give bsdeform-run --sweep's numbers
to the last bit and its sweep.csv / sweep.png byte for byte: through a real `dask scheduler`
with two `dask worker` processes on 127.0.0.1, with one of them killed mid-sweep, and on the
default local cluster; a failing value is a row with its status and message; a field the scene
does not have is refused before anything is submitted. Every process the tests start is stopped
at the end, also when a test fails."""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import distributed

import bsdeform
from support import RUN, scene

SEC7 = scene("paper_sec7_central_square.iv")
W10 = ["0", "0.0001", "0.001", "0.01", "0.1", "1"]
TIMEOUT = 120  # s, for any one step of a test (a cluster starting, a sweep, a reference run)


def reference(tmp, values, target="Surface.w10", until="1", sets=(), metrics=()):
    """bsdeform-run --sweep's sweep.csv and sweep.png (bytes)."""
    out = os.path.join(tmp, "reference")
    args = [RUN, SEC7, "--until", until, "--sweep", "%s=%s" % (target, ",".join(values)), "-o", out, "--quiet"]
    for s in sets:
        args += ["--set", s]
    for m in metrics:
        args += ["--metric", m]
    r = subprocess.run(args, capture_output=True, text=True, timeout=TIMEOUT)
    if r.returncode != 0:
        raise AssertionError("bsdeform-run --sweep failed (%d): %s" % (r.returncode, r.stderr))
    with open(os.path.join(out, "sweep.csv"), "rb") as f:
        csv_bytes = f.read()
    with open(os.path.join(out, "sweep.png"), "rb") as f:
        png_bytes = f.read()
    shutil.rmtree(out)
    return csv_bytes, png_bytes


def csv_rows(data):
    return list(csv.DictReader(data.decode().splitlines()))


def stop(process):
    """Ends a process started in its own session and everything it started (a worker's nanny,
    worker process and bsdeform-run children)."""
    if process.poll() is None:
        try:
            os.killpg(process.pid, signal.SIGTERM)
            process.wait(timeout=10)
        except (ProcessLookupError, subprocess.TimeoutExpired):
            pass
    try:
        os.killpg(process.pid, signal.SIGKILL)  # whatever is left of the group
    except ProcessLookupError:
        pass
    process.wait(timeout=10)


class Cluster:
    """A `dask scheduler` and `dask worker`s on 127.0.0.1 (free ports: the scheduler picks one
    and writes it into its scheduler file), each in its own process group."""

    def __init__(self, test_case, workers):
        self.dir = tempfile.mkdtemp(prefix="bsdeform-dask-test-")
        test_case.addClassCleanup(shutil.rmtree, self.dir, True)
        self.file = os.path.join(self.dir, "scheduler.json")
        self.processes = {}
        self.logs = []
        self._start(test_case, "scheduler", ["scheduler", "--host", "127.0.0.1", "--port", "0", "--no-dashboard",
                                             "--scheduler-file", self.file])
        deadline = time.monotonic() + TIMEOUT
        while not os.path.exists(self.file):
            if time.monotonic() > deadline or self.processes["scheduler"].poll() is not None:
                raise AssertionError("the scheduler did not start: " + self.log("scheduler"))
            time.sleep(0.1)
        time.sleep(0.2)  # the file is written whole, but let it be closed
        with open(self.file) as f:
            self.address = json.load(f)["address"]
        for i in range(workers):
            self._start(test_case, "w%d" % i, ["worker", "--scheduler-file", self.file, "--host", "127.0.0.1",
                                               "--nthreads", "1", "--no-dashboard", "--name", "w%d" % i,
                                               "--local-directory", os.path.join(self.dir, "w%d" % i)])
        self.client = distributed.Client(self.address, timeout="%ds" % TIMEOUT)
        test_case.addClassCleanup(self.client.close)
        self.client.wait_for_workers(workers, timeout=TIMEOUT)

    def _start(self, test_case, name, args):
        log = open(os.path.join(self.dir, name + ".log"), "w")
        self.logs.append(log)
        test_case.addClassCleanup(log.close)
        p = subprocess.Popen([sys.executable, "-m", "dask"] + args, stdout=log, stderr=subprocess.STDOUT,
                             stdin=subprocess.DEVNULL, start_new_session=True)
        self.processes[name] = p
        test_case.addClassCleanup(stop, p)  # cleanups run last in, first out: workers before the scheduler

    def log(self, name):
        with open(os.path.join(self.dir, name + ".log")) as f:
            return f.read()[-3000:]

    def worker_names(self):
        return {addr: w["name"] for addr, w in self.client.scheduler_info()["workers"].items()}


class OnACluster(unittest.TestCase):
    """A scheduler and two workers, shared by the tests of this class."""

    @classmethod
    def setUpClass(cls):
        cls.cluster = Cluster(cls, 2)

    def setUp(self):
        self.tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, self.tmp, True)

    def test_six_values_give_bsdeform_runs_numbers_csv_and_plot(self):
        ref_csv, ref_png = reference(self.tmp, W10)
        out = os.path.join(self.tmp, "dask")
        seen = []
        result = bsdeform.sweep(SEC7, {"Surface.w10": W10}, until=1, client=self.cluster.client, out=out,
                                progress=lambda done, total, run: seen.append((done, total)))
        self.assertEqual([run.values["Surface.w10"] for run in result], W10)  # in the order of the values
        self.assertEqual(seen[-1], (6, 6))
        with open(os.path.join(out, "sweep.csv"), "rb") as f:
            self.assertEqual(f.read(), ref_csv)
        with open(os.path.join(out, "sweep.png"), "rb") as f:
            self.assertEqual(f.read(), ref_png)
        # every number, as a double
        for row, ref in zip(result.rows, csv_rows(ref_csv), strict=True):
            self.assertEqual(row.value, ref["value"])
            self.assertEqual(row.surface, ref["surface"])
            self.assertEqual((row.norm, row.kinetic, row.strain), (float(ref["norm"]), float(ref["kinetic"]),
                                                                    float(ref["strain"])))
            self.assertEqual(row.status, "ok")
        self.assertEqual(len({row.norm for row in result.rows}), 6)  # the values made a difference
        self.assertEqual(sorted(os.listdir(out)), ["sweep.csv", "sweep.png"])  # no scratch left

    def test_metrics_give_bsdeform_runs_columns_and_plot(self):
        # issue 37, item 6: --metric through Dask, the same bytes as bsdeform-run --sweep --metric
        metrics = ["y@0.5:0.5", "max-stretch", "rest-time"]
        ref_csv, ref_png = reference(self.tmp, W10[:3], metrics=metrics)
        out = os.path.join(self.tmp, "dask")
        result = bsdeform.sweep(SEC7, {"Surface.w10": W10[:3]}, until=1, client=self.cluster.client, out=out,
                                metrics=metrics, progress=False)
        with open(os.path.join(out, "sweep.csv"), "rb") as f:
            self.assertEqual(f.read(), ref_csv)
        with open(os.path.join(out, "sweep.png"), "rb") as f:
            self.assertEqual(f.read(), ref_png)
        self.assertTrue(ref_csv.decode().startswith(
            "value,surface,norm,kinetic,strain,status,y@0.5:0.5,max-stretch,rest-time\n"))
        for row, ref in zip(result.rows, csv_rows(ref_csv), strict=True):
            self.assertEqual(row.metrics["y@0.5:0.5"], float(ref["y@0.5:0.5"]))
            self.assertGreater(row.metrics["max-stretch"], 1.0)
        with self.assertRaises(ValueError):
            bsdeform.sweep(SEC7, {"Surface.w10": ["1"]}, until=1, client=self.cluster.client, metrics=["w@2"])

    def test_the_command_line_on_the_scheduler(self):
        ref_csv, ref_png = reference(self.tmp, W10[:3])
        out = os.path.join(self.tmp, "cli")
        r = subprocess.run([sys.executable, "-m", "bsdeform", "sweep", SEC7, "--sweep", "Surface.w10=" + ",".join(W10[:3]),
                            "--until", "1", "--scheduler", self.cluster.address, "-o", out],
                           capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn(ref_csv.decode(), r.stdout)
        # --keep-outputs: each run's final.iv and history as a single bsdeform-run writes them
        kept = os.path.join(self.tmp, "kept")
        r = subprocess.run([sys.executable, "-m", "bsdeform", "sweep", SEC7, "--sweep", "Surface.w10=" + ",".join(W10[:2]),
                            "--until", "1", "--scheduler", self.cluster.address, "-o", kept, "--keep-outputs", "-q"],
                           capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(r.stdout, "")
        single = os.path.join(self.tmp, "single")
        subprocess.run([RUN, SEC7, "--until", "1", "--set", "Surface.w10=" + W10[1], "-o", single, "--quiet"],
                       check=True, timeout=TIMEOUT)
        for name in ("Surface.csv", "final.iv"):
            with open(os.path.join(kept, "runs", "1", name), "rb") as a, open(os.path.join(single, name), "rb") as b:
                self.assertEqual(a.read(), b.read(), name)
        with open(os.path.join(out, "sweep.csv"), "rb") as f:
            self.assertEqual(f.read(), ref_csv)
        with open(os.path.join(out, "sweep.png"), "rb") as f:
            self.assertEqual(f.read(), ref_png)
        # the same directory again: not empty, bad input (2), nothing replaced
        before = os.stat(os.path.join(out, "sweep.csv")).st_mtime_ns
        r = subprocess.run([sys.executable, "-m", "bsdeform", "sweep", SEC7, "--sweep", "Surface.w10=1,2",
                            "--scheduler", self.cluster.address, "-o", out], capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("is not empty", r.stderr)
        self.assertEqual(os.stat(os.path.join(out, "sweep.csv")).st_mtime_ns, before)

    def test_two_fields_give_every_combination_and_the_histories(self):
        result = bsdeform.sweep(SEC7, {"Surface.w10": ["0.01", "1"], "Surface.w01": ["0.1", "0.5"]}, until=1,
                                client=self.cluster.client, keep_outputs=True, progress=False)
        self.assertEqual([tuple(run.values.values()) for run in result],
                         [("0.01", "0.1"), ("0.01", "0.5"), ("1", "0.1"), ("1", "0.5")])
        for w01 in ("0.1", "0.5"):
            ref_csv, _ = reference(self.tmp, ["0.01", "1"], sets=["Surface.w01=" + w01])
            got = [r for r in result.rows if r.values["Surface.w01"] == w01]
            for row, ref in zip(got, csv_rows(ref_csv), strict=True):
                self.assertEqual((row.value, row.norm, row.kinetic, row.strain),
                                 (ref["value"], float(ref["norm"]), float(ref["kinetic"]), float(ref["strain"])))
        zipped = bsdeform.sweep(SEC7, {"Surface.w10": ["0.01", "1"], "Surface.w01": ["0.1", "0.5"]}, until=1,
                                client=self.cluster.client, zip=True, progress=False)
        self.assertEqual([tuple(run.values.values()) for run in zipped], [("0.01", "0.1"), ("1", "0.5")])
        self.assertEqual(zipped.rows[1].norm, result.rows[3].norm)
        # the final scene and history: a single bsdeform-run's files
        out = os.path.join(self.tmp, "single")
        subprocess.run([RUN, SEC7, "--until", "1", "--set", "Surface.w10=1", "--set", "Surface.w01=0.5", "-o", out,
                        "--quiet"], check=True, timeout=TIMEOUT)
        with open(os.path.join(out, "Surface.csv")) as f:
            self.assertEqual(result[3].histories["Surface"], f.read())
        with open(os.path.join(out, "final.iv")) as f:
            self.assertEqual(result[3].final_scene, f.read())

    def test_a_failing_value_is_a_row_with_its_status_and_message(self):
        # -0.5 parses (Coin) but the model refuses it; 1e12 makes the explicit scheme blow up
        result = bsdeform.sweep(SEC7, {"Surface.timeStep": ["0.1", "-0.5"]}, until=1, client=self.cluster.client,
                                out=os.path.join(self.tmp, "fail"), progress=False)
        ok, bad = result
        self.assertEqual(ok.status, "ok")
        self.assertEqual(bad.status, "failed")
        (row,) = bad.rows
        self.assertEqual((row.surface, row.norm, row.status), ("Surface", None, "failed"))
        for part in ("paper_sec7_central_square.iv", "timeStep", "-0.5"):
            self.assertIn(part, row.message)
        self.assertNotIn("bsdeform-sweep-", row.message)  # names the user's scene, not the scratch copy
        with open(os.path.join(self.tmp, "fail", "sweep.csv")) as f:
            lines = f.read().splitlines()
        self.assertEqual(lines[2], "-0.5,Surface,,,,failed")
        with open(os.path.join(self.tmp, "fail", "sweep_failures.txt")) as f:
            self.assertIn("Surface.timeStep=-0.5: ", f.read())

        blown = bsdeform.sweep(SEC7, {"Square.magnitude": ["100", "1e12"]}, until=1, client=self.cluster.client,
                               progress=False)
        self.assertEqual([run.status for run in blown], ["ok", "blew-up"])
        row = blown[1].rows[0]
        self.assertEqual(row.status, "blew-up")
        self.assertIn("Surface", row.message)
        ref_csv, _ = reference(self.tmp, ["100", "1e12"], target="Square.magnitude")
        for row, ref in zip(blown.rows, csv_rows(ref_csv), strict=True):
            self.assertEqual((row.norm, row.status), (float(ref["norm"]), ref["status"]))

        # a run longer than `timeout` is stopped and is a failed row
        slow = bsdeform.sweep(SEC7, {"Surface.w10": ["1"]}, until=1000, client=self.cluster.client, timeout=0.3,
                              sets=["Surface.numUControlPoints=256", "Surface.numVControlPoints=256"], progress=False)
        self.assertEqual(slow[0].status, "failed")
        self.assertIn("timed out after 0.3 s", slow[0].message)

        # the command line: the rows are written, the exit code is bsdeform-run's for a failed run (1)
        r = subprocess.run([sys.executable, "-m", "bsdeform", "sweep", SEC7, "--sweep", "Surface.timeStep=0.1,-0.5",
                            "--until", "1", "--scheduler", self.cluster.address, "-o", os.path.join(self.tmp, "cli"), "-q"],
                           capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(r.returncode, 1, r.stderr)
        self.assertIn("Surface.timeStep=-0.5 failed", r.stderr)
        self.assertTrue(os.path.exists(os.path.join(self.tmp, "cli", "sweep.csv")))

    def test_a_field_the_scene_lacks_is_refused_before_anything_is_submitted(self):
        class NoSubmit:
            def submit(self, *args, **kwargs):
                raise AssertionError("a task was submitted")

        out = os.path.join(self.tmp, "never")
        cases = [({"Surface.stiffness": ["1"]}, ["paper_sec7_central_square.iv", "'Surface' has no field 'stiffness'"]),
                 ({"Nobody.w10": ["1"]}, ["no node or engine is DEF'ed as 'Nobody'"]),
                 ({"Surface.w10": ["0.1", "abc"]}, ["'abc' is not a valid value for field Surface.w10"]),
                 ({"Surface.integrator": ["EXPLICIT", "SIDEWAYS"]}, ["SIDEWAYS", "Surface.integrator"])]
        for fields, parts in cases:
            with self.subTest(fields=fields):
                with self.assertRaises(bsdeform.FieldError) as cm:
                    bsdeform.sweep(SEC7, fields, until=1, client=NoSubmit(), out=out)
                for part in parts:
                    self.assertIn(part, str(cm.exception))
                self.assertFalse(os.path.exists(out))
        with self.assertRaises(bsdeform.FieldError):
            bsdeform.sweep(SEC7, {"Surface.w10": [1]}, until=1, client=NoSubmit(), sets=["Surface.nope=1"])
        # the command line: bad input (2), nothing written
        before = self.cluster.client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks))
        r = subprocess.run([sys.executable, "-m", "bsdeform", "sweep", SEC7, "--sweep", "Surface.stiffness=1,2",
                            "--scheduler", self.cluster.address, "-o", out], capture_output=True, text=True, timeout=TIMEOUT)
        self.assertEqual(r.returncode, 2, r.stderr)
        self.assertIn("'Surface' has no field 'stiffness'", r.stderr)
        self.assertFalse(os.path.exists(out))
        self.assertEqual(self.cluster.client.run_on_scheduler(lambda dask_scheduler: len(dask_scheduler.tasks)), before)


class AKilledWorker(unittest.TestCase):
    """One of two workers is killed (SIGKILL, with its nanny and its bsdeform-run) while it runs
    a task: its tasks run again on the other and the numbers do not change."""

    @classmethod
    def setUpClass(cls):
        cls.cluster = Cluster(cls, 2)

    def test_the_sweep_completes_with_the_same_numbers(self):
        tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, tmp, True)
        # runs long enough (about a second each) that the other worker is busy when one finishes
        sets = ["Surface.numUControlPoints=48", "Surface.numVControlPoints=48"]
        ref_csv, ref_png = reference(tmp, W10, until="3", sets=sets)
        cluster = self.cluster
        killed = {}

        def kill_a_busy_worker(done, total, run):
            if killed:
                return
            processing = cluster.client.processing()
            names = cluster.worker_names()
            busy = [names[a] for a, keys in processing.items() if any(k.startswith("bsdeform-run-") for k in keys)]
            if busy:
                victim = busy[0]
                killed.update(name=victim, done=done)
                os.killpg(cluster.processes[victim].pid, signal.SIGKILL)

        out = os.path.join(tmp, "dask")
        result = bsdeform.sweep(SEC7, {"Surface.w10": W10}, until=3, sets=sets, client=cluster.client, out=out,
                                progress=kill_a_busy_worker)
        self.assertTrue(killed, "no worker was busy after the first result")
        self.assertLess(killed["done"], 6)
        self.assertEqual(cluster.processes[killed["name"]].wait(timeout=10), -signal.SIGKILL)
        self.assertEqual(len(cluster.worker_names()), 1)
        self.assertEqual([run.status for run in result], ["ok"] * 6)
        with open(os.path.join(out, "sweep.csv"), "rb") as f:
            self.assertEqual(f.read(), ref_csv)
        with open(os.path.join(out, "sweep.png"), "rb") as f:
            self.assertEqual(f.read(), ref_png)


class TheRunnersWriter(unittest.TestCase):
    """bsdeform-run --sweep-rows (internal: what bsdeform.sweep writes its files with) refuses
    rows that are not a sweep.csv, and writes a failed run's row without plotting it."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, self.tmp, True)

    def write(self, text):
        path = os.path.join(self.tmp, "rows.csv")
        with open(path, "w") as f:
            f.write(text)
        return subprocess.run([RUN, SEC7, "--sweep", "Surface.w10=1,2", "--sweep-rows", path, "-o",
                               os.path.join(self.tmp, "out"), "--quiet"], capture_output=True, text=True, timeout=TIMEOUT)

    def test_bad_rows_are_bad_input(self):
        r = self.write("value,norm\n1,2\n")
        self.assertEqual(r.returncode, 2)
        self.assertIn("not sweep.csv's header", r.stderr)
        r = self.write("value,surface,norm,kinetic,strain,status\n1,Surface,0.5,0,0\n")
        self.assertEqual(r.returncode, 2)
        self.assertIn("line 2: expected 6 columns, got 5", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, "out")))

    def test_rows_are_written_as_given(self):
        rows = "value,surface,norm,kinetic,strain,status\n1,Surface,0.5,0.25,0.125,ok\n2,Surface,,,,failed\n"
        r = self.write(rows)
        self.assertEqual(r.returncode, 0, r.stderr)
        with open(os.path.join(self.tmp, "out", "sweep.csv")) as f:
            self.assertEqual(f.read(), rows)
        self.assertTrue(os.path.getsize(os.path.join(self.tmp, "out", "sweep.png")) > 1000)


class OneThreadARun(unittest.TestCase):
    """The runs of a sweep fill the workers' cores beside each other: each gets one kernel thread
    (bsdeform-run's default is every CPU) unless the worker's environment names a count."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, self.tmp, True)
        self.child = os.path.join(self.tmp, "child.sh")
        with open(self.child, "w") as f:
            f.write("#!/bin/sh\nprintf 'RESULT\\tSurface\\t1\\t0\\t0\\t%s\\n' \"${BSDEFORM_THREADS:-unset}\"\n")
        os.chmod(self.child, 0o755)

    def threads_seen(self):
        task = {"scene_name": "s.iv", "sets": [], "values": {"Surface.w10": "1"}, "surfaces": ["Surface"],
                "steps": 1, "program": self.child}
        (row,) = bsdeform._sweep.run_task("#Inventor V2.1 ascii\n", task).rows
        return row.status

    def test_one_thread_unless_the_environment_says(self):
        saved = os.environ.pop("BSDEFORM_THREADS", None)
        try:
            self.assertEqual(self.threads_seen(), "1")
            os.environ["BSDEFORM_THREADS"] = "3"
            self.assertEqual(self.threads_seen(), "3")
        finally:
            os.environ.pop("BSDEFORM_THREADS", None)
            if saved is not None:
                os.environ["BSDEFORM_THREADS"] = saved


class OnTheLocalDefault(unittest.TestCase):
    def test_client_none_starts_and_closes_a_local_cluster(self):
        tmp = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, tmp, True)
        ref_csv, _ = reference(tmp, W10[:4])
        result = bsdeform.sweep(SEC7, {"Surface.w10": W10[:4]}, until=1, workers=2, progress=False)
        self.assertEqual(result.csv.encode(), ref_csv)
        # the cluster's processes are gone: no child of this process is left (a closing
        # worker may take a moment to exit)
        deadline = time.monotonic() + 20
        while children() and time.monotonic() < deadline:
            time.sleep(0.2)
        self.assertEqual(children(), [])


def children():
    """The live processes whose parent is this one, but for multiprocessing's resource tracker
    (Python's own, started with the first process the interpreter spawns; it ends with it)."""
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open("/proc/%s/stat" % pid) as f:
                fields = f.read().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == os.getpid() and fields[0] != "Z":
            with open("/proc/%s/cmdline" % pid, "rb") as f:
                if b"multiprocessing.resource_tracker" not in f.read():
                    found.append(int(pid))
    return found

if __name__ == "__main__":
    unittest.main()
