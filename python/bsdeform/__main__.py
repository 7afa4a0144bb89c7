# SPDX-License-Identifier: MIT
"""python3 -m bsdeform sweep SCENE --sweep NAME.field=v1,v2,... [--until T] [--scheduler ADDR] -o DIR

bsdeform-run --sweep on Dask (docs/python.md, "Sweeps"). The options it shares with
bsdeform-run mean the same, and so do the exit codes: 0 success (a blow-up is a row, not a
failure), 2 bad input (scene, names, values, options, output directory; nothing was submitted),
4 an output file could not be written (the previous file is kept), 1 a run failed (its row and
message are written), the scheduler could not be reached, a command line the parser cannot read
(as bsdeform-run's parser), or an internal error.
"""
import argparse
import math
import os
import sys

EXIT_OK, EXIT_INTERNAL, EXIT_BAD_INPUT, EXIT_WRITE_FAILED = 0, 1, 2, 4


class _Parser(argparse.ArgumentParser):
    # A line the parser cannot read (an unknown option, a missing value) exits with 1, as
    # bsdeform-run's (QCommandLineParser::process) does; values it reads but refuses are 2.
    def error(self, message):
        self.print_usage(sys.stderr)
        self.exit(EXIT_INTERNAL, "%s: %s\n" % (self.prog, message))


def _parser():
    p = _Parser(prog="python3 -m bsdeform", description="bsdeform from the command line.")
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)
    s = sub.add_parser(
        "sweep", help="bsdeform-run --sweep on Dask: one run per value, on this machine or a cluster",
        description="Runs the scene once per value (or combination of values) as Dask tasks, each one "
                    "bsdeform-run --set ... on a worker, and writes sweep.csv and sweep.png as bsdeform-run --sweep "
                    "does. Exit codes: 0 success, 2 bad input, 4 an output file could not be written (the previous "
                    "file is kept), 1 a run failed (its row says why) or the scheduler could not be reached.")
    s.add_argument("scene", help="the .iv scene")
    s.add_argument("--sweep", action="append", required=True, metavar="NAME.field=v1,v2,...",
                   help="the values of a field (repeatable: every combination, or --zip)")
    s.add_argument("--zip", action="store_true", help="the i-th values of every --sweep together, not their product")
    s.add_argument("--metric", action="append", default=[], metavar="METRIC",
                   help="measure over each run, as bsdeform-run --metric (repeatable): z@U:V, max-z@U:V, min-z@U:V "
                        "(or x, y), stretch, max-stretch, kinetic, rest-time; a column of sweep.csv each, the first "
                        "plotted")
    s.add_argument("--set", action="append", default=[], metavar="NAME.field=value",
                   help="override a field in every run: NAME is a DEF name (repeatable)")
    s.add_argument("-n", "--steps", metavar="N", help="number of steps (default 100)")
    s.add_argument("-t", "--until", metavar="T", help="run until simulated time T")
    s.add_argument("-o", "--out", metavar="DIR", help="output directory (default: <scene name>.out); must be empty or new")
    s.add_argument("--overwrite", action="store_true", help="allow replacing files in a non-empty output directory")
    s.add_argument("--scheduler", metavar="ADDRESS",
                   help="a running Dask scheduler (tcp://host:8786); default: a local cluster of processes")
    s.add_argument("--workers", metavar="N", help="workers of the local cluster (default: one per core)")
    s.add_argument("--timeout", metavar="S", help="seconds a run may take; a longer one is a failed row")
    s.add_argument("--retries", metavar="N", default="2", help="Dask's retries of a task that raised (default 2)")
    s.add_argument("--keep-outputs", action="store_true",
                   help="also write each run's final scene and history CSVs into DIR/runs/<index>/")
    s.add_argument("-q", "--quiet", action="store_true", help="no summary, no progress")
    return p


def _count(text, option, minimum):
    try:
        n = int(text)
    except ValueError:
        n = None
    if n is None or n < minimum:
        raise ValueError("%s '%s' is not a count >= %d" % (option, text, minimum))
    return n


def _seconds(text, option, positive):
    try:
        x = float(text)
    except ValueError:
        x = math.nan
    if not math.isfinite(x) or x < 0 or (positive and x == 0):
        raise ValueError("%s '%s' is not a time %s 0" % (option, text, ">" if positive else ">="))
    return x


def _fields(specs):
    fields = {}
    for spec in specs:
        eq = spec.find("=")
        if eq <= 0:
            raise ValueError("--sweep '%s': expected NAME.field=v1,v2,..." % spec)
        values = [v for v in spec[eq + 1:].split(",") if v]
        if not values:
            raise ValueError("--sweep '%s': no values" % spec)
        if spec[:eq] in fields:
            raise ValueError("--sweep '%s': %s is swept twice" % (spec, spec[:eq]))
        fields[spec[:eq]] = values
    return fields


def _write_run_outputs(result, out):
    # --keep-outputs: DIR/runs/<index>/final.iv and <surface>.csv, as a single bsdeform-run writes them
    from ._sweep import _save
    written = []
    for i, run in enumerate(result):
        d = os.path.join(out, "runs", "%d" % i)
        os.makedirs(d, exist_ok=True)
        files = dict(("%s.csv" % k, v) for k, v in (run.histories or {}).items())
        if run.final_scene is not None:
            files["final.iv"] = run.final_scene
        for name, text in files.items():
            _save(os.path.join(d, "." + name + ".tmp"), text, os.path.join(d, name))
            written.append(os.path.join(d, name))
    return written


def sweep_main(a):
    import bsdeform
    from bsdeform import _sweep

    try:
        steps = _count(a.steps, "--steps", 0) if a.steps is not None else None
        until = _seconds(a.until, "--until", False) if a.until is not None else None
        if steps is not None and until is not None:
            raise ValueError("give --steps or --until, not both")
        workers = _count(a.workers, "--workers", 1) if a.workers is not None else None
        timeout = _seconds(a.timeout, "--timeout", True) if a.timeout is not None else None
        retries = _count(a.retries, "--retries", 0)
        if a.scheduler and workers:
            raise ValueError("--workers sizes the local cluster: not with --scheduler")
        fields = _fields(a.sweep)
    except ValueError as e:
        return _fail(EXIT_BAD_INPUT, str(e))
    out = a.out or os.path.splitext(os.path.basename(a.scene))[0] + ".out"
    if not os.path.exists(a.scene):
        return _fail(EXIT_BAD_INPUT, "cannot open scene '%s': no such file" % a.scene)
    if os.path.isdir(a.scene):
        return _fail(EXIT_BAD_INPUT, "cannot open scene '%s': it is a directory" % a.scene)

    client = None
    if a.scheduler:
        from distributed import Client
        try:
            client = Client(a.scheduler, timeout="20s")
        except (OSError, TimeoutError) as e:
            return _fail(EXIT_INTERNAL, "cannot reach the Dask scheduler '%s': %s" % (a.scheduler, e))
    try:
        try:
            result = bsdeform.sweep(a.scene, fields, steps=steps, until=until, client=client, zip=a.zip, sets=a.set,
                                    out=out, overwrite=a.overwrite, keep_outputs=a.keep_outputs, workers=workers,
                                    retries=retries, timeout=timeout, progress=None if not a.quiet else False,
                                    metrics=a.metric)
        except _sweep.WriteError as e:
            return _fail(EXIT_WRITE_FAILED, str(e))
        except (bsdeform.FieldError, bsdeform.SceneError, ValueError) as e:
            return _fail(EXIT_BAD_INPUT, str(e))
        except bsdeform.Error as e:
            return _fail(EXIT_INTERNAL, str(e))
        except Exception as e:  # Dask's own (a task whose workers kept dying: KilledWorker, ...)
            return _fail(EXIT_INTERNAL, "the sweep stopped: %s: %s" % (type(e).__name__, e))
        written = result.written
        if a.keep_outputs:
            try:
                written += _write_run_outputs(result, out)
            except OSError as e:
                return _fail(EXIT_WRITE_FAILED, "cannot write the runs' outputs into '%s': %s" % (out, e))
        where = a.scheduler or "a local cluster"
        if not a.quiet:
            print("bsdeform: sweep of %s over %d run(s) on %s" % (", ".join(result.fields), len(result), where))
            sys.stdout.write(result.csv)
            for w in written:
                print("  wrote %s" % w)
        failed = result.failed
        for run in failed:
            sys.stderr.write("bsdeform: run with %s failed: %s\n" % (
                " ".join("%s=%s" % kv for kv in run.values.items()), run.message))
        return EXIT_INTERNAL if failed else EXIT_OK
    finally:
        if client is not None:
            client.close()


def _fail(code, message):
    sys.stderr.write("bsdeform: %s\n" % message)
    return code


def main(argv=None):
    a = _parser().parse_args(argv)
    if a.command != "sweep":
        _parser().print_help(sys.stderr)
        return EXIT_BAD_INPUT
    return sweep_main(a)


if __name__ == "__main__":
    sys.exit(main())
