# SPDX-License-Identifier: MIT
"""Stepping, reset, diagnostics and live fields from Python, against the C++ runner's numbers.

bsdeform-run (C++) writes a CSV row per step with 17 significant digits; the same scene run
from Python must give the same doubles (same code path, same order of operations).
"""
import csv
import os
import subprocess
import tempfile
import unittest

import bsdeform
from support import RUN, scene

COLUMNS = ("time", "step", "norm", "kinetic", "strain", "strain_w10", "strain_w01", "strain_w11",
           "strain_w20", "strain_w02", "substeps", "strain_membrane", "strain_bending")


def runner_rows(scene_name, steps):
    with tempfile.TemporaryDirectory() as d:
        out = os.path.join(d, "out")
        subprocess.run([RUN, scene(scene_name), "--steps", str(steps), "-o", out, "--quiet"], check=True,
                       capture_output=True, timeout=300)
        rows = {}
        for f in os.listdir(out):
            if f.endswith(".csv"):
                with open(os.path.join(out, f)) as fh:
                    rows[f[:-4]] = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(fh)]
        return rows


def python_rows(scene_name, steps):
    bsdeform.simulated_clock(0.0)  # before reading: engines note their start time (as the runner)
    root = bsdeform.read_scene(scene(scene_name))
    surfaces = bsdeform.surfaces(root)
    names = [s.name or "surface%d" % i for i, s in enumerate(surfaces)]  # the runner's names
    rows = {n: [] for n in names}

    def record(i, s):
        d = s.diagnostics()
        t = d["strain_terms"]
        rows[names[i]].append({"time": d["time"], "step": d["steps"], "norm": d["norm"], "kinetic": d["kinetic"],
                             "strain": d["strain"], "strain_w10": t["w10"], "strain_w01": t["w01"],
                             "strain_w11": t["w11"], "strain_w20": t["w20"], "strain_w02": t["w02"],
                             "substeps": d["sub_steps"], "strain_membrane": d["strain_membrane"],
                             "strain_bending": d["strain_bending"]})

    # as the runner: realTime follows simulated time (the engines of animated_force.iv read it)
    from pivy import coin
    real_time = coin.SoDB.getGlobalField("realTime")
    for i, s in enumerate(surfaces):
        s.node.on.setValue(False)
        record(i, s)
    dt = min(s.time_step for s in surfaces)
    for k in range(1, steps + 1):
        real_time.setValue(k * dt)
        for i, s in enumerate(surfaces):
            s.step(1)
            record(i, s)
    return rows


def decimal15(x):
    """A time as bsdeform-run's CSV writes it: its 15-significant-digit value."""
    return float("%.15g" % x)


@unittest.skipUnless(RUN, "bsdeform-run is not built (BSDEFORM_BUILD_UI=OFF)")
class AgainstTheRunner(unittest.TestCase):
    def check_scene(self, name, steps):
        expected = runner_rows(name, steps)
        got = python_rows(name, steps)
        self.assertEqual(sorted(expected), sorted(got))
        for surface, rows in expected.items():
            self.assertEqual(len(rows), steps + 1)
            self.assertEqual(len(got[surface]), steps + 1)
            for want, have in zip(rows, got[surface]):
                for c in COLUMNS:
                    # the CSV writes the time at its 15-digit value (0.3, not 0.30000000000000004)
                    value = decimal15(have[c]) if c == "time" else have[c]
                    self.assertEqual(value, want[c], "%s %s step %d column %s" % (name, surface, want["step"], c))
            self.assertGreater(rows[-1]["norm"], 0.0)

    def test_region_load_20_steps(self):
        self.check_scene("region_load.iv", 20)

    def test_engine_driven_scene_follows_the_same_clock(self):
        self.check_scene("animated_force.iv", 15)

    def test_run_helper_gives_the_runner_history(self):
        expected = runner_rows("animated_force.iv", 12)
        bsdeform.simulated_clock()
        histories = bsdeform.run(bsdeform.read_scene(scene("animated_force.iv")), steps=12)
        self.assertEqual(sorted(histories), sorted(expected))
        for name, h in histories.items():
            self.assertEqual(list(h.norm), [r["norm"] for r in expected[name]])
            self.assertEqual([decimal15(t) for t in h.time], [r["time"] for r in expected[name]])


class Stepping(unittest.TestCase):
    def setUp(self):
        self.root = bsdeform.read_scene(scene("region_load.iv"))
        (self.surface,) = bsdeform.surfaces(self.root)
        self.node = self.surface.node

    def test_live_fields_step_reset(self):
        s = self.surface
        s.step(7)
        self.assertEqual(s.step_count, 7)
        # the fields pivy reads are current (not only after writing the scene)
        self.assertEqual(self.node.stepCount.getValue(), 7)
        self.assertEqual(self.node.simulationTime.getValue(), s.time)
        self.assertAlmostEqual(s.time, 7 * s.time_step, places=12)
        d = s.diagnostics()
        self.assertEqual(d["steps"], 7)
        self.assertEqual(d["status"], "ok")
        self.assertAlmostEqual(d["norm"], s.norm, delta=1e-12 * s.norm)  # one pass vs the per-term function
        self.assertGreater(d["norm"], 0.0)
        self.assertGreater(d["kinetic"], 0.0)
        self.assertAlmostEqual(d["strain"], sum(d["strain_terms"].values()), delta=1e-12 * d["strain"])
        self.assertGreater(d["stability_limit"], 0.0)
        self.assertGreaterEqual(d["sub_steps"], 1)
        self.assertLessEqual(d["time_step"] / d["sub_steps"], d["stability_limit"])
        s.reset()
        self.assertEqual(s.step_count, 0)
        self.assertEqual(s.norm, 0.0)
        self.assertEqual(self.node.stepCount.getValue(), 0)
        self.assertEqual(self.node.simulationTime.getValue(), 0.0)
        # the reset trigger touched through pivy does the same
        s.step(2)
        self.node.reset.touch()
        self.assertEqual(s.step_count, 0)

    def test_steps_in_one_call_equal_steps_one_by_one(self):
        other = bsdeform.surfaces(bsdeform.read_scene(scene("region_load.iv")))[0]
        self.surface.step(9)
        for _ in range(9):
            other.step(1)
        self.assertEqual(self.surface.diagnostics(), other.diagnostics())

    def test_field_edits_through_pivy_take_effect(self):
        self.surface.step(5)
        soft = self.surface.diagnostics()
        self.surface.reset()
        bsdeform.set_field(self.node, "w10", 5.0)  # through Coin's field reader
        self.node.w01.setValue(5.0)                # through pivy's setValue
        self.surface.step(5)
        stiff = self.surface.diagnostics()
        self.assertNotEqual(stiff["norm"], soft["norm"])
        # the same as a scene that has these values in its file
        with open(scene("region_load.iv")) as f:
            text = f.read().replace("SoBSplineDeformSurface {", "SoBSplineDeformSurface { w10 5 w01 5", 1)
        (from_file,) = bsdeform.surfaces(bsdeform.read_scene_text(text))
        from_file.step(5)
        self.assertEqual(from_file.diagnostics(), stiff)

    def test_a_node_created_from_code_is_a_surface(self):
        node = bsdeform.new_node("SoBSplineDeformSurface", numUControlPoints=8, numVControlPoints=6, on=False)
        force = bsdeform.new_node("SoForceField", type="UNIFORM", force=(0, 0, 10))
        node.forces.setValue(force)
        s = bsdeform.Surface(node)
        self.assertEqual(s.net_shape, (14, 12, 3))
        s.step(4)
        self.assertGreater(s.evaluate(0.5, 0.5)[2], 0.0)


class Probe(unittest.TestCase):
    def test_probe_is_the_point_and_its_displacement_as_the_runner_writes_them(self):
        (beam,) = bsdeform.surfaces(bsdeform.read_scene(scene("cantilever.iv")))
        p = beam.probe(1.0, 0.5)
        self.assertEqual(sorted(p), ["displacement", "point"])
        self.assertEqual(p["displacement"], (0.0, 0.0, 0.0))  # at rest
        self.assertAlmostEqual(p["point"][0], 1.0, places=12)
        beam.step(3)
        p = beam.probe(1.0, 0.5)
        self.assertEqual(p["point"], beam.evaluate(1.0, 0.5))
        self.assertLess(p["displacement"][2], 0.0)  # the tip falls
        self.assertEqual(beam.probe(0.0, 0.5)["displacement"], (0.0, 0.0, 0.0))  # the clamped root stays
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            subprocess.run([RUN, scene("cantilever.iv"), "--steps", "3", "--probe", "tip=1,0.5", "-o", out,
                            "--quiet"], check=True, capture_output=True, timeout=300)
            with open(os.path.join(out, "Strip.csv")) as fh:
                row = list(csv.DictReader(fh))[-1]
        self.assertEqual(p["point"], tuple(float(row["tip_" + a]) for a in "xyz"))
        self.assertEqual(p["displacement"], tuple(float(row["tip_d" + a]) for a in "xyz"))
        with self.assertRaisesRegex(ValueError, "u must be in \\[0, 1\\], got 1.5"):
            beam.probe(1.5, 0.5)
        with self.assertRaisesRegex(ValueError, "v must be in"):
            beam.probe(0.5, -1)


class Static(unittest.TestCase):
    def test_solve_static_is_the_runners_equilibrium_and_holds_still(self):
        (beam,) = bsdeform.surfaces(bsdeform.read_scene(scene("cantilever.iv")))
        result = beam.solve_static()
        self.assertLess(result["residual"], 1e-10)
        self.assertEqual(result["method"], "CHOLMOD Cholesky")
        self.assertEqual(result["load_iterations"], 1)
        # the beam's tip q L^4 / (8 D) = 0.25, downwards; at rest at t = 0
        self.assertAlmostEqual(beam.evaluate(1.0, 0.5)[2], -0.25, places=9)
        self.assertEqual(beam.time, 0.0)
        self.assertEqual(beam.diagnostics()["kinetic"], 0.0)
        # the same numbers as bsdeform-run --static
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            subprocess.run([RUN, scene("cantilever.iv"), "--static", "-o", out, "--quiet"], check=True,
                           capture_output=True, timeout=300)
            with open(os.path.join(out, "Strip.csv")) as fh:
                (row,) = list(csv.DictReader(fh))
        self.assertEqual(float(row["norm"]), beam.diagnostics()["norm"])

    def test_reactions_balance_the_loads_as_the_runner_writes_them(self):
        (plate,) = bsdeform.surfaces(bsdeform.read_scene(scene("plate_simply_supported.iv")))
        result = plate.solve_static(load_steps=2)
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            subprocess.run([RUN, scene("plate_simply_supported.iv"), "--static", "--load-steps", "2", "-o", out,
                            "--quiet"], check=True, capture_output=True, timeout=300)
            with open(os.path.join(out, "Plate.csv")) as fh:
                rows = list(csv.DictReader(fh))
        self.assertEqual(len(rows), 2)
        for inc, row in zip(result["increments"], rows):
            self.assertEqual(sorted(inc["reactions"]), ["umax", "umin", "vmax", "vmin"])
            applied = inc["applied"]
            self.assertGreater(abs(applied[2]), 1.0)
            for c in range(3):
                total = applied[c] + sum(r[c] for r in inc["reactions"].values())
                self.assertLess(abs(total), 1e-10 * abs(applied[2]))
            for side, force in inc["reactions"].items():
                self.assertAlmostEqual(force[2], -applied[2] / 4, delta=1e-10 * abs(applied[2]))  # symmetry
                for c, axis in enumerate("xyz"):
                    self.assertEqual(force[c], float(row["reaction_%s_%s" % (side, axis)]))
            self.assertEqual(applied, tuple(float(row["applied_" + a]) for a in "xyz"))

    def test_arc_length_follows_the_roof_through_its_limit_point_as_the_runner_does(self):
        (roof,) = bsdeform.surfaces(bsdeform.read_scene(scene("hinged_roof_snap.iv")))
        result = roof.solve_static(arc_length=True, load_steps=60, max_load=1.0)
        loads = [inc["load_factor"] for inc in result["increments"]]
        peak = next(k for k in range(len(loads) - 1) if loads[k + 1] < loads[k])  # the limit point
        self.assertGreater(peak, 0)
        self.assertLess(min(loads[peak:]), 0.5 * loads[peak])  # through the limit point: the load falls
        self.assertEqual(loads[-1], 1.0)                          # and rises again to the full load, ending there
        for inc in result["increments"]:
            self.assertLess(inc["residual"], 1e-8)
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "out")
            subprocess.run([RUN, scene("hinged_roof_snap.iv"), "--static", "--arc-length", "--load-steps", "60",
                            "-o", out, "--quiet"], check=True, capture_output=True, timeout=300)
            with open(os.path.join(out, "Roof.csv")) as fh:
                rows = list(csv.DictReader(fh))
        self.assertEqual(len(rows), len(loads))
        for r, l in zip(rows, loads):  # the CSV writes 15 significant digits
            self.assertAlmostEqual(float(r["load_factor"]), l, delta=1e-14 * max(1.0, abs(l)))
        with self.assertRaisesRegex(ValueError, "max_load"):
            roof.solve_static(arc_length=True, max_load=0.0)

    def test_a_surface_held_nowhere_names_its_free_motions(self):
        node = bsdeform.new_node("SoBSplineDeformSurface", numUControlPoints=6, numVControlPoints=6, on=False,
                                 boundaryUMin="FREE", boundaryUMax="FREE", boundaryVMin="FREE",
                                 boundaryVMax="FREE")
        node.forces.setValue(bsdeform.new_node("SoForceField", type="UNIFORM", force=(0, 0, 1)))
        s = bsdeform.Surface(node)
        with self.assertRaisesRegex(bsdeform.SimulationError, "translations"):
            s.solve_static()
        self.assertEqual(s.norm, 0.0)  # the state is left alone


if __name__ == "__main__":
    unittest.main()
