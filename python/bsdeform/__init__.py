# SPDX-License-Identifier: MIT
"""bsdeform for pivy: B-spline finite-element surface deformation nodes in Coin3D.

``import bsdeform`` imports ``pivy.coin`` and registers SoBSplineDeformSurface and SoForceField
in the Coin that pivy uses (no dlopen flags needed, before or after ``import pivy.coin``). Scenes
read by pivy or by :func:`read_scene` then contain real nodes, which :class:`Surface` steps,
resets and measures; :func:`render` draws any scene offscreen (EGL, no X server).

    import bsdeform
    root = bsdeform.read_scene("scenes/region_load.iv")   # a pivy.coin.SoSeparator
    (surface,) = bsdeform.surfaces(root)
    surface.step(20)
    print(surface.diagnostics()["norm"])
    image = bsdeform.render(root, 640, 480)               # numpy uint8 (480, 640, 3)

See docs/python.md.
"""
import pivy.coin as coin  # first: the C++ module finds pivy's SWIG types through it

from ._errors import Error, FieldError, RenderError, SceneError, SimulationError
from ._bsdeform import (SceneRunner, Surface, export_mesh, read_scene, read_scene_text, render, render_png,
                        scene_text, surfaces)

__all__ = [
    "Error", "FieldError", "RenderError", "SceneError", "SimulationError",
    "SceneRunner", "Surface", "export_mesh", "read_scene", "read_scene_text", "render", "render_png", "scene_text",
    "surfaces",
    "set_field", "new_node", "run", "History", "simulated_clock",
    "sweep", "Run", "Row", "SweepResult",
]


def _label(node):
    name = node.getName().getString()
    return "%s '%s'" % (node.getTypeId().getName().getString(), name or "<unnamed>")


def _field_text(value):
    if isinstance(value, str):
        return value
    if isinstance(value, bool):
        return "TRUE" if value else "FALSE"
    if isinstance(value, (int, float)):
        return repr(value)
    try:  # a vector or a list of vectors
        items = list(value)
    except TypeError:
        return str(value)
    if items and all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in items):
        return " ".join(repr(v) for v in items)  # one vector
    return "[ " + ", ".join(_quoted(v) if isinstance(v, str) else _field_text(v) for v in items) + " ]"


def _quoted(text):
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def set_field(node, name, value):
    """Sets field `name` of a pivy node from a Python value or .iv text (``"0.3"``,
    ``"IMPLICIT"``, ``(0, 0, 5)``, ``[(0.2, 0.3), (0.8, 0.3)]``, a list of strings for an
    MFString). Raises FieldError naming node,
    field and value when the node has no such field or Coin cannot parse the value. Values
    that parse but are out of range (a negative time step) are refused by the surface when it
    next builds its model: Surface.check() or step() raise FieldError then."""
    field = node.getField(name)
    if field is None:
        raise FieldError("%s: no field '%s'" % (_label(node), name))
    text = _field_text(value)
    if not field.set(text):
        raise FieldError("%s: field '%s': '%s' is not a valid value" % (_label(node), name, text))


def _surface_set(self, **fields):
    """Sets fields by name (see set_field), then builds the model: a refused value raises
    FieldError at once."""
    for name, value in fields.items():
        set_field(self.node, name, value)
    self.check()


Surface.set = _surface_set


def new_node(type_name, **fields):
    """A new node or engine of a registered Coin type (``"SoBSplineDeformSurface"``,
    ``"SoForceField"``, ``"Cube"``, ...) as a pivy proxy, fields set with set_field()."""
    t = coin.SoType.fromName(type_name)
    if t.isBad() or not t.canCreateInstance():
        raise Error("no Coin type '%s' that can be created" % type_name)
    node = t.createInstance()
    for name, value in fields.items():
        set_field(node, name, value)
    return node


def simulated_clock(time=0.0):
    """Makes Coin's global realTime field a simulated clock, as bsdeform-run does: the sensor
    that sets it to the wall-clock time is switched off and it is set to `time`; run() then
    advances it with the simulation. Call it before reading a scene whose engines use realTime
    (ElapsedTime, TimeCounter, ...): they note the start time when they are created, and run()
    then repeats bsdeform-run's numbers exactly. Not for interactive viewers, whose engines need
    the real clock."""
    coin.SoDB.enableRealTimeSensor(False)
    coin.SoDB.getGlobalField("realTime").setValue(time)


class History:
    """What run() records per surface: NumPy arrays time, step, norm, kinetic, strain."""

    def __init__(self):
        self._rows = []

    def _add(self, d):
        self._rows.append((d["time"], d["steps"], d["norm"], d["kinetic"], d["strain"]))

    def __len__(self):
        return len(self._rows)

    def __getattr__(self, name):
        columns = ("time", "step", "norm", "kinetic", "strain")
        if name not in columns:
            raise AttributeError(name)
        import numpy
        return numpy.array([r[columns.index(name)] for r in self._rows])


def run(root, steps=None, until=None, record_every=1):
    """Runs every surface of the scene as bsdeform-run does (one SceneRunner): Coin's realTime
    follows the simulated time (engines driven by it animate deterministically when
    simulated_clock() was called before the scene was read), each surface takes its own steps
    of timeStep up to the common time. Give `steps` (of the smallest timeStep) or
    `until` (simulated time). Returns {surface name (or "surface<i>"): History} with the
    first state, every state whose step count is a multiple of record_every, and the last.
    Raises FieldError for a refused field value before anything runs, SimulationError when a
    surface blows up (its history up to then is lost with the exception)."""
    if (steps is None) == (until is None):
        raise ValueError("give exactly one of steps and until")
    runner = SceneRunner(root)
    found = runner.surfaces
    if not found:
        raise Error("the scene has no SoBSplineDeformSurface")
    for s in found:
        s.check()
    dt = runner.time_step
    t0 = runner.start_time
    frames = steps if steps is not None else max(0, round((until - t0) / dt))
    histories = {}
    for i, s in enumerate(found):
        histories[s.name or "surface%d" % i] = History()
    named = list(zip(found, histories.values()))
    for s, h in named:
        h._add(s.diagnostics())

    def stepped(i):
        s, h = named[i]
        if s.step_count % record_every == 0 or s.status != "ok":
            h._add(s.diagnostics())

    runner.advance_to(t0)
    for frame in range(1, frames + 1):
        if not runner.advance_to(t0 + frame * dt, stepped):
            bad = [(s, n) for (s, _), n in zip(named, histories) if s.status != "ok"]
            raise SimulationError("; ".join("%s: the simulation stopped (%s): %s" % (n, s.status, s.status_message)
                                            for s, n in bad))
    for s, h in named:
        if h._rows[-1][1] != s.step_count:
            h._add(s.diagnostics())
    return histories


# Last: _sweep uses _field_text above. Dask (python3-distributed) is imported only when a sweep runs.
from ._sweep import Row, Run, SweepResult, sweep  # noqa: E402
