# SPDX-License-Identifier: MIT
"""Parameter sweeps on Dask: ``bsdeform-run --sweep`` beyond one machine (docs/python.md, "Sweeps").

One Dask task per combination of values. A task is a pure function of (scene text, overrides,
run length): on the worker it writes the scene text into a private directory and runs
``bsdeform-run SCENE --set NAME.field=value ... --result-only``, the command bsdeform-run's own
sweep starts per value, and returns that run's rows. The numbers are therefore bsdeform-run's to
the last bit, a crash or a hung run ends one subprocess (a row with status "failed"), not the
worker, and a worker never holds Coin state between tasks. sweep.csv and sweep.png are written
by bsdeform-run's own writer (``--sweep-rows``): the same bytes and the same plot.

distributed (Debian python3-distributed) is imported only when a sweep runs: ``import bsdeform``
does not need it.
"""
import itertools
import math
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

from ._errors import Error, FieldError, SceneError

CSV_HEADER = "value,surface,norm,kinetic,strain,status"
# bsdeform-run --metric's names (ui/run/Metrics.h); bsdeform-run checks the numbers too
_METRIC = re.compile(r"^(stretch|max-stretch|kinetic|rest-time|(max-|min-)?[xyz]@[^:,]+:[^:,]+)$")
STATUS_OK, STATUS_BLEW_UP, STATUS_FAILED = "ok", "blew-up", "failed"

# bsdeform-run's exit codes (README.md, `bsdeform-run --help`).
EXIT_OK, EXIT_INTERNAL, EXIT_BAD_INPUT, EXIT_BLOW_UP, EXIT_WRITE_FAILED = 0, 1, 2, 3, 4


class InputError(Error, ValueError):
    """Bad input that is neither a scene nor a field: the output directory, bsdeform-run missing."""


class Row:
    """One surface's final state in one run: the row of sweep.csv.

    ``values`` maps each swept NAME.field to its value text; ``value`` is the value of the first
    (the only one in a one-field sweep). ``norm``, ``kinetic`` and ``strain`` are floats (None
    in a failed run), exactly the numbers bsdeform-run printed (the shortest text that reads back);
    ``status`` is "ok", "blew-up" (the last finite state is reported) or "failed" (the run did
    not finish: a value the model refused, a crash, a timeout); ``message`` says why."""

    __slots__ = ("values", "surface", "norm", "kinetic", "strain", "status", "message", "metrics", "_text",
                 "_metric_text")

    def __init__(self, values, surface, texts, status, message="", metrics=()):
        self.values = dict(values)
        self.surface = surface
        self._text = tuple(texts)  # as bsdeform-run printed them: sweep.csv keeps these bytes
        self.norm, self.kinetic, self.strain = (float(t) if t else None for t in texts)
        self.status = status
        self.message = message
        # ``metrics``: (name, text) pairs as bsdeform-run --metric printed them; the attribute
        # maps each name to its float (None in a failed run; nan: not at rest by the end)
        self._metric_text = tuple(t for _, t in metrics)
        self.metrics = {name: float(t) if t else None for name, t in metrics}

    @property
    def value(self):
        return next(iter(self.values.values()))

    def csv_fields(self):
        return [self.surface, *self._text, self.status, *self._metric_text]

    def __repr__(self):
        return "Row(%s, %s, norm=%r, kinetic=%r, strain=%r, status=%r%s)" % (
            ", ".join("%s=%s" % kv for kv in self.values.items()), self.surface, self.norm, self.kinetic,
            self.strain, self.status, ", message=%r" % self.message if self.message else "")


class Run:
    """One combination's run: ``values`` (NAME.field -> value text), ``rows`` (one per surface),
    ``status`` ("ok", "blew-up", "failed": the worst of its rows), ``message``, and with
    ``keep_outputs=True`` ``final_scene`` (final.iv's text) and ``histories`` ({surface: the
    history CSV text bsdeform-run writes}); ``seconds``: the wall time of its bsdeform-run on the
    worker."""

    __slots__ = ("values", "rows", "message", "final_scene", "histories", "seconds")

    def __init__(self, values, rows, message="", final_scene=None, histories=None):
        self.values, self.rows, self.message = dict(values), rows, message
        self.final_scene, self.histories = final_scene, histories
        self.seconds = None

    @property
    def status(self):
        statuses = {r.status for r in self.rows}
        for s in (STATUS_FAILED, STATUS_BLEW_UP):
            if s in statuses:
                return s
        return STATUS_OK

    def __repr__(self):
        return "Run(%s: %s)" % (", ".join("%s=%s" % kv for kv in self.values.items()), self.status)


class SweepResult(list):
    """The runs of a sweep in the order of the values (a list of Run), with ``rows`` (every
    row, in that order), ``csv`` (sweep.csv's text), ``fields`` (the swept NAME.field names) and
    ``written`` (the files written, when ``out`` was given)."""

    def __init__(self, runs, fields, metrics=()):
        super().__init__(runs)
        self.fields = list(fields)
        self.metrics = list(metrics)
        self.written = []

    @property
    def rows(self):
        return [r for run in self for r in run.rows]

    @property
    def failed(self):
        return [run for run in self if run.status == STATUS_FAILED]

    @property
    def csv(self):
        return _csv_text(self.fields, self.rows, self.metrics)


def _csv_text(fields, rows, metrics=()):
    # One field: bsdeform-run's sweep.csv, byte for byte. More: one column per field first.
    # Then one column per metric (bsdeform-run --metric).
    header = CSV_HEADER if len(fields) == 1 else ",".join(fields) + CSV_HEADER[len("value"):]
    header = ",".join([header, *metrics])
    lines = [header]
    for r in rows:
        lines.append(",".join([r.values[f] for f in fields] + r.csv_fields()))
    return "\n".join(lines) + "\n"


def value_text(value):
    """The .iv text of a value as a sweep passes it to ``--set``: a str as it is, a bool as
    TRUE/FALSE, a number by repr() (0.1 -> "0.1"), as set_field() does."""
    from . import _field_text
    return _field_text(value)


def find_program(program=None):
    """bsdeform-run: `program`, else $BSDEFORM_RUN, else the one on PATH. Raises Error when
    there is none (the message says what was tried)."""
    candidate = program or os.environ.get("BSDEFORM_RUN") or shutil.which("bsdeform-run")
    if not candidate:
        raise InputError("bsdeform-run not found: not on PATH and BSDEFORM_RUN is not set (a sweep runs it on every worker)")
    if not (os.path.isfile(candidate) and os.access(candidate, os.X_OK)):
        raise InputError("bsdeform-run '%s' is not an executable file" % candidate)
    return os.path.abspath(candidate)  # the task runs it from its own directory


# ---------------------------------------------------------------------------------------------
# The task: runs on a worker.

def _scratch_root():
    # The worker's own directory when there is one: Dask removes a dead worker's directory when
    # the next worker starts on that machine, so a killed worker leaves nothing behind for long.
    try:
        from distributed import get_worker
        return get_worker().local_directory
    except (ImportError, ValueError, AttributeError):
        return None


def _run_lines(stdout, metrics=0):
    found = []
    for line in stdout.splitlines():
        c = line.split("\t")
        if len(c) == 6 + metrics and c[0] == "RESULT":
            found.append(c[1:])
    return found


def run_task(scene_text, task):
    """Runs one combination with bsdeform-run in a subprocess and returns its Run.

    `task` is a dict: ``scene_name`` (the file name the scene had: messages name it),
    ``sets`` (NAME.field=value, fixed ones first), ``values`` (the swept NAME.field -> value),
    ``surfaces`` (the scene's surface names, for the rows of a run that did not finish),
    ``steps`` or ``until``, ``keep_outputs``, ``timeout`` (s, or None), ``program`` (None: found
    on the worker). Pure: the same arguments give the same Run; it writes only into a
    directory of its own, removed at the end, so running it again (Dask's retries, a task
    moved off a dead worker) is harmless."""
    program = find_program(task.get("program"))
    work = tempfile.mkdtemp(prefix="bsdeform-sweep-", dir=_scratch_root())
    try:
        scene_path = os.path.join(work, task["scene_name"])
        with open(scene_path, "w", encoding="utf-8") as f:
            f.write(scene_text)
        args = [program, scene_path]
        if task.get("until") is not None:
            args += ["--until", repr(float(task["until"]))]
        else:
            args += ["--steps", str(int(task["steps"]))]
        for s in task["sets"]:
            args += ["--set", s]
        for m in task.get("metrics", ()):
            args += ["--metric", m]
        out = os.path.join(work, "out")
        args += ["-o", out, "--quiet", "--result-lines"] if task.get("keep_outputs") else ["--result-only"]
        started = time.monotonic()
        try:
            # one kernel thread per run unless the worker's environment says otherwise: the
            # runs of a sweep already fill the cores beside each other
            env = dict(os.environ)
            if not env.get("BSDEFORM_THREADS"):
                env["BSDEFORM_THREADS"] = "1"
            p = subprocess.run(args, stdin=subprocess.DEVNULL, capture_output=True, timeout=task.get("timeout"),
                               cwd=work, start_new_session=True, env=env)
            code, stdout, stderr = p.returncode, p.stdout.decode("utf-8", "replace"), p.stderr.decode("utf-8", "replace")
        except subprocess.TimeoutExpired:
            code, stdout, stderr = None, "", "timed out after %g s" % task["timeout"]
        run = _make_run(task, code, stdout, _message(stderr, scene_path, task["scene_name"]), out)
        run.seconds = time.monotonic() - started
        return run
    finally:
        shutil.rmtree(work, ignore_errors=True)


def _message(stderr, scene_path, scene_name):
    # bsdeform-run's own lines (Qt may add notes of its own, e.g. about XDG_RUNTIME_DIR), naming
    # the user's scene, not the scratch copy.
    text = stderr.replace(scene_path, scene_name).strip()
    own = [line[len("bsdeform-run: "):] for line in text.splitlines() if line.startswith("bsdeform-run: ")]
    return "; ".join(own) if own else text


def _make_run(task, code, stdout, stderr, out):
    values = task["values"]
    metrics = list(task.get("metrics", ()))
    lines = _run_lines(stdout, len(metrics))
    if code is not None and code < 0:
        sig = -code
        try:
            name = signal.Signals(sig).name
        except ValueError:
            name = "signal %d" % sig
        stderr = "bsdeform-run crashed (%s)%s" % (name, ": " + stderr if stderr else "")
    elif code not in (EXIT_OK, None) and not stderr:
        stderr = "bsdeform-run exited with code %d" % code
    if not lines or code not in (EXIT_OK, EXIT_BLOW_UP, EXIT_BAD_INPUT):
        # Did not finish (or finished in a way bsdeform-run's sweep counts as a failure): one
        # row per surface of the scene, without numbers.
        return Run(values, [Row(values, s, ("", "", ""), STATUS_FAILED, stderr, [(m, "") for m in metrics])
                            for s in task["surfaces"]], stderr)
    rows = [Row(values, c[0], c[1:4], c[4], stderr if c[4] != STATUS_OK else "", list(zip(metrics, c[5:])))
            for c in lines]
    run = Run(values, rows, stderr if code != EXIT_OK else "")
    if task.get("keep_outputs") and os.path.isdir(out):
        histories = {}
        for r in rows:
            path = os.path.join(out, r.surface + ".csv")
            if os.path.isfile(path):
                with open(path, encoding="utf-8") as f:
                    histories[r.surface] = f.read()
        run.histories = histories
        final = os.path.join(out, "final.iv")
        if os.path.isfile(final):
            with open(final, encoding="utf-8") as f:
                run.final_scene = f.read()
    return run


# ---------------------------------------------------------------------------------------------
# The client side.

def _combinations(fields, zipped):
    names = list(fields)
    lists = []
    for name in names:
        values = fields[name]
        if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
            raise FieldError("sweep %s: expected a list of values, got %r" % (name, values))
        texts = [value_text(v) for v in values]
        if not texts:
            raise FieldError("sweep %s: no values" % name)
        for t in texts:
            if "," in t or "\n" in t:
                raise FieldError("sweep %s='%s': a value with a comma or a line break cannot be a sweep.csv column" % (name, t))
        lists.append(texts)
    if zipped:
        lengths = {len(v) for v in lists}
        if len(lengths) != 1:
            raise FieldError("zip=True needs as many values for every field, got %s" % ", ".join(
                "%s: %d" % (n, len(v)) for n, v in zip(names, lists)))
        combos = zip(*lists)
    else:
        combos = itertools.product(*lists)
    return names, [dict(zip(names, c)) for c in combos]


def _split_spec(spec):
    eq = spec.find("=")
    dot = spec.rfind(".", 0, eq) if eq > 0 else -1
    if eq <= 0 or dot <= 0 or dot + 1 >= eq:
        raise FieldError("--set '%s': expected NAME.field=value" % spec)
    return spec[:dot], spec[dot + 1:eq], spec[eq + 1:]


def _apply(spec, scene_name):
    # bsdeform-run's applySet (ui/run/RunSetup.cpp), with its messages: the node or engine
    # DEF'ed as NAME, its field, Coin's parser for the value.
    import pivy.coin as coin
    name, field_name, value = _split_spec(spec)
    base = coin.SoBase.getNamedBase(coin.SbName(name), coin.SoFieldContainer.getClassTypeId())
    if base is None:
        raise FieldError("%s: --set '%s': no node or engine is DEF'ed as '%s' in the scene" % (scene_name, spec, name))
    field = base.getField(field_name)
    if field is None:
        raise FieldError("%s: --set '%s': '%s' has no field '%s'" % (scene_name, spec, name, field_name))
    if not field.set(value):
        raise FieldError("%s: --set '%s': '%s' is not a valid value for field %s.%s (%s)" % (
            scene_name, spec, value, name, field_name, field.getTypeId().getName().getString()))


def validate(scene, sets, combos):
    """Reads the scene and applies every fixed --set and every swept value to it, as
    bsdeform-run --sweep does before it starts a run: a missing node, a missing field or a
    value Coin cannot parse raises FieldError naming the scene, field and value. Returns the
    scene's surface names (DEF name, or "surface<i>")."""
    from . import read_scene, surfaces
    root = read_scene(scene)
    for s in sets:
        _apply(s, scene)
    for combo in combos:
        for name, v in combo.items():
            _apply("%s=%s" % (name, v), scene)
    found = surfaces(root)
    if not found:
        raise SceneError("scene '%s' has no SoBSplineDeformSurface" % scene)
    return [s.name or "surface%d" % i for i, s in enumerate(found)]


class _Progress:
    # bsdeform-run's progress bar (ui/run/RunSetup.cpp), on stderr when it is a terminal.
    def __init__(self):
        self.last = -1

    def __call__(self, done, total, run):
        pct = int(100 * done / total)
        if pct == self.last and done != total:
            return
        self.last = pct
        filled = pct // 4
        sys.stderr.write("\r[%s%s] %3d%%  %d of %d run(s)" % ("#" * filled, "." * (25 - filled), pct, done, total))
        if done == total:
            sys.stderr.write("\n")
        sys.stderr.flush()


def prepare_out_dir(out, overwrite):
    """bsdeform-run's rule for the output directory: new, empty, or overwrite=True; raises
    InputError otherwise."""
    if os.path.exists(out) and not os.path.isdir(out):
        raise InputError("output path '%s' is not a directory" % out)
    if os.path.isdir(out) and os.listdir(out) and not overwrite:
        raise InputError("output directory '%s' is not empty; nothing was written (use --overwrite to replace its files)" % out)
    try:
        os.makedirs(out, exist_ok=True)
        with tempfile.TemporaryFile(dir=out, prefix=".bsdeform-write-test-"):
            pass
    except OSError as e:
        raise InputError("output directory '%s' is not usable: %s" % (out, e.strerror or e)) from None


class WriteError(Error, OSError):
    """sweep.csv, sweep.png or sweep_failures.txt could not be written (the previous file is
    kept)."""


def write_outputs(result, scene, out, program=None):
    """Writes sweep.csv and sweep.png into `out` with bsdeform-run's own writer, and
    sweep_failures.txt (NAME.field=value: message, one line per run) when a run failed or blew
    up with a message. Each file is replaced only when complete. Returns the paths written."""
    program = find_program(program)
    fields = result.fields
    rows = result.rows
    first = fields[0]
    if len(fields) == 1:
        plot_rows = rows
    else:
        # the plot: the norm against the first field, one line per surface and value of the others
        plot_rows = [Row({first: r.values[first]},
                         "%s %s" % (r.surface, " ".join("%s=%s" % (f, r.values[f]) for f in fields[1:])),
                         r._text, r.status, "", list(zip(result.metrics, r._metric_text))) for r in rows]
    plot_values = []
    for r in plot_rows:
        if r.value not in plot_values:
            plot_values.append(r.value)
    written = []
    work = tempfile.mkdtemp(prefix=".bsdeform-sweep-", dir=out)
    try:
        rows_path = os.path.join(work, "rows.csv")
        with open(rows_path, "w", encoding="utf-8") as f:
            f.write(_csv_text([first], plot_rows, result.metrics))
        args = [program, scene, "--sweep", "%s=%s" % (first, ",".join(plot_values)), "--sweep-rows", rows_path,
                "-o", os.path.join(work, "w"), "--quiet"]
        for m in result.metrics:
            args += ["--metric", m]
        p = subprocess.run(args, stdin=subprocess.DEVNULL, capture_output=True)
        if p.returncode != 0:
            message = p.stderr.decode("utf-8", "replace").strip()
            if p.returncode == EXIT_WRITE_FAILED:
                raise WriteError(message)
            raise Error("bsdeform-run could not write the sweep's results: %s" % message)
        made = os.path.join(work, "w")
        csv_path = os.path.join(out, "sweep.csv")
        if len(fields) == 1:
            os.replace(os.path.join(made, "sweep.csv"), csv_path)
        else:
            _save(os.path.join(work, "sweep.csv"), result.csv, csv_path)
        written.append(csv_path)
        if os.path.exists(os.path.join(made, "sweep.png")):
            os.replace(os.path.join(made, "sweep.png"), os.path.join(out, "sweep.png"))
            written.append(os.path.join(out, "sweep.png"))
        messages = ["%s: %s" % (" ".join("%s=%s" % kv for kv in run.values.items()), run.message)
                    for run in result if run.message]
        if messages:
            path = os.path.join(out, "sweep_failures.txt")
            _save(os.path.join(work, "sweep_failures.txt"), "\n".join(messages) + "\n", path)
            written.append(path)
    except WriteError:
        raise
    except OSError as e:
        raise WriteError("cannot write the sweep's results into '%s': %s" % (out, e)) from None
    finally:
        shutil.rmtree(work, ignore_errors=True)
    return written


def _save(tmp, text, path):
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
        f.flush()
        os.fsync(f.fileno())
    os.replace(tmp, path)


def sweep(scene, fields, steps=None, until=None, client=None, zip=False, sets=(), out=None, overwrite=False,
          keep_outputs=False, workers=None, retries=2, timeout=None, program=None, worker_program=None,
          progress=None, metrics=()):
    """Runs `scene` once per combination of `fields` on Dask and returns a SweepResult (a list
    of Run, in the order of the values).

    scene:     path of the .iv scene (its text is what the workers get).
    fields:    {"NAME.field": [values, ...]}: every combination (their product), or, with
               zip=True, the i-th value of each field together. Values are .iv text or Python
               values (see value_text()).
    steps, until: the run length, as bsdeform-run --steps / --until (default: 100 steps).
    client:    a distributed.Client (any cluster); None starts a LocalCluster of `workers`
               processes (default: one per core), one thread each, closed at the end.
    sets:      NAME.field=value overrides applied to every run before the swept values.
    out:       a directory for sweep.csv and sweep.png (new, empty, or overwrite=True).
    keep_outputs: also bring back each run's final scene text and history CSVs.
    retries:   Dask's retries of a task that raised (a worker that dies is handled by the
               scheduler: its tasks run again elsewhere).
    timeout:   seconds per run; a run that takes longer is a "failed" row.
    program:   bsdeform-run on this machine (writes sweep.csv/png); worker_program the path on
               the workers (default: $BSDEFORM_RUN or PATH there).
    progress:  None (a bar on stderr when it is a terminal), True, False, or a callable
               progress(done, total, run) called as each run arrives.
    metrics:   what each run measures besides the final norm, as bsdeform-run --metric
               ("z@0.5:0.5", "max-z@0.5:0.5", "min-z@U:V", "stretch", "max-stretch", "kinetic",
               "rest-time"): a column of sweep.csv each, the first plotted, and Row.metrics.

    A field or value the scene refuses raises FieldError before anything is submitted; a run
    that fails is a Run with status "failed" and its message, not an exception."""
    if steps is not None and until is not None:
        raise ValueError("give steps or until, not both")
    if until is not None and not (isinstance(until, (int, float)) and math.isfinite(until) and until >= 0):
        raise ValueError("until=%r is not a time >= 0" % (until,))
    if steps is not None and not (isinstance(steps, int) and steps >= 0):
        raise ValueError("steps=%r is not a count >= 0" % (steps,))
    if until is None and steps is None:
        steps = 100
    if not fields:
        raise FieldError("sweep: no field to sweep")
    metrics = list(metrics)
    for m in metrics:
        if not _METRIC.match(m):
            raise ValueError("metric %r is not one of z@U:V (or x, y; U, V in [0, 1]), max-z@U:V, min-z@U:V, "
                             "stretch, max-stretch, kinetic, rest-time" % (m,))
    scene = os.fspath(scene)
    sets = list(sets)
    for s in sets:
        _split_spec(s)
    names, combos = _combinations(fields, zip)
    surfaces = validate(scene, sets, combos)
    program = find_program(program) if out is not None else program
    if out is not None:
        prepare_out_dir(out, overwrite)
    try:
        with open(scene, encoding="utf-8") as f:
            scene_text = f.read()
    except (OSError, UnicodeDecodeError) as e:
        raise SceneError("cannot open scene '%s': %s" % (scene, e)) from None

    tasks = [{"scene_name": os.path.basename(scene), "sets": sets + ["%s=%s" % kv for kv in combo.items()],
              "values": combo, "surfaces": surfaces, "steps": steps, "until": until,
              "keep_outputs": bool(keep_outputs), "timeout": timeout, "program": worker_program,
              "metrics": metrics}
             for combo in combos]
    if progress is None:
        progress = _Progress() if sys.stderr.isatty() else None
    elif progress is True:
        progress = _Progress()
    elif progress is False:
        progress = None

    own = None
    if client is None:
        own = _local_client(workers)
        client = own[1]
    try:
        runs = _gather(client, scene_text, tasks, retries, progress)
    finally:
        if own is not None:
            own[1].close()
            own[0].close()
    result = SweepResult(runs, names, metrics)
    if out is not None:
        result.written = write_outputs(result, scene, out, program)
    return result


def _local_client(workers):
    from distributed import Client, LocalCluster
    n = workers or os.cpu_count() or 1
    # Processes, one thread each: every task waits on a subprocess, and a worker that dies
    # takes only its own task with it.
    cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True, dashboard_address=None)
    try:
        return cluster, Client(cluster)
    except BaseException:
        cluster.close()
        raise


def _gather(client, scene_text, tasks, retries, progress):
    from dask.base import tokenize
    from distributed import as_completed
    # Each task carries the scene text itself: no task depends on another, so the scheduler
    # places every one on any free worker (a shared input would pin short tasks to the worker
    # holding it), and a worker that dies holds nothing another task needs.
    futures = []
    for i, task in enumerate(tasks):
        key = "bsdeform-run-%d-%s" % (i, tokenize(scene_text, task))
        futures.append(client.submit(run_task, scene_text, task, key=key, pure=True, retries=retries))
    index = {f.key: i for i, f in enumerate(futures)}
    runs = [None] * len(futures)
    try:
        done = 0
        for future in as_completed(futures):
            runs[index[future.key]] = future.result()  # raises the task's exception after its retries
            done += 1
            if progress:
                progress(done, len(futures), runs[index[future.key]])
    finally:
        client.cancel(futures)
    return runs
