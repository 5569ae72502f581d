"""The Python module of the prediction API, run by ctest with Debian's python3:
shapes and types, determinism, label round trips, changes that change the
prediction, errors as Python exceptions, adaptive sampling."""
import os
import sys
import tempfile
import unittest

import numpy as np

import printlight

SCENE = sys.argv.pop(1)


class PredictorTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.p = printlight.Predictor(SCENE)
        cls.p.spp = 1
        cls.p.seed = 3
        cls.p.channels = "g"
        cls.p.integrator = "volpath"

    def test_prediction_arrays(self):
        r = self.p.predict()
        n = self.p.surface_voxel_count
        self.assertEqual(r["voxels"].shape, (n, 3))
        self.assertEqual(r["radiance"].shape, (n, 3))
        self.assertEqual(r["stderr"].shape, (n, 3))
        self.assertEqual(r["samples"].dtype, np.uint32)
        self.assertTrue(np.all(r["samples"] == 1))
        g = r["radiance"][:, 1]
        self.assertTrue(np.all(np.isfinite(g)))
        self.assertTrue(0.05 < g.mean() < 1.0, g.mean())   # a printed cube under white light
        self.assertTrue(np.all(r["radiance"][:, 0] == 0))   # channels not rendered stay 0
        labels = self.p.labels()
        v = r["voxels"]
        lo = np.array(self.p.grid_min)
        self.assertTrue(np.all(labels[v[:, 2] - lo[2], v[:, 1] - lo[1], v[:, 0] - lo[0]] != self.p.void_label))

    def test_deterministic_and_round_trip(self):
        a = self.p.predict()
        b = self.p.predict()
        self.assertTrue(np.array_equal(a["radiance"], b["radiance"]))
        self.p.set_labels(self.p.labels())
        c = self.p.predict()
        self.assertTrue(np.array_equal(a["radiance"], c["radiance"]))

    def test_changes_change_the_prediction_where_they_are(self):
        before = self.p.predict()
        v = before["voxels"][:2000]
        old = self.p.labels()[v[:, 2], v[:, 1], v[:, 0]].copy()
        black = np.full(len(v), 3, dtype=np.uint8)
        self.p.change_labels(v, black)
        after = self.p.predict()
        # Blackened surface voxels get darker on average; far voxels barely change.
        self.assertLess(after["radiance"][:2000, 1].mean(), 0.8 * before["radiance"][:2000, 1].mean())
        self.p.change_labels(v, old)   # undo
        self.assertTrue(np.array_equal(self.p.predict()["radiance"], before["radiance"]))

    def test_carry_over_adds_samples_and_retraces_what_changes_reach(self):
        self.p.carry_over = True
        try:
            first = self.p.predict()
            self.assertTrue(first["started_afresh"])
            v = first["voxels"][:50]
            old = self.p.labels()[v[:, 2], v[:, 1], v[:, 0]].copy()
            self.p.change_labels(v, np.full(len(v), 3, dtype=np.uint8))
            second = self.p.predict()
            self.assertFalse(second["started_afresh"])
            self.assertTrue(np.all(second["samples"] == 2))
            self.assertTrue(0 < second["retraced_voxels"] < self.p.surface_voxel_count)
            self.p.change_labels(v, old)   # undo
        finally:
            self.p.carry_over = False

    def test_errors_are_python_exceptions(self):
        with self.assertRaises(ValueError):
            self.p.change_labels(np.array([[0, 0, 0]]), np.array([9], dtype=np.uint8))   # no material 9
        with self.assertRaises(IndexError):
            self.p.change_labels(np.array([[100000, 0, 0]]), np.array([4], dtype=np.uint8))
        with self.assertRaises(ValueError):
            self.p.change_labels(np.zeros((2, 2)), np.zeros(2, dtype=np.uint8))
        with self.assertRaises(ValueError):
            self.p.set_labels(np.zeros((2, 2, 2), dtype=np.uint8))
        with self.assertRaises(ValueError):
            self.p.channels = "x"
        with self.assertRaises(ValueError):
            self.p.channel_sampling = "x"
        with self.assertRaises(RuntimeError):
            printlight.Predictor("/nonexistent/scene.json")

    def test_rgb_in_one_pass(self):
        self.p.channels = "rgb"
        self.p.channel_sampling = "hero"
        self.p.spp = 3
        try:
            r = self.p.predict()
        finally:
            self.p.channels = "g"
            self.p.channel_sampling = "separate"
            self.p.spp = 1
        self.assertTrue(np.all(r["samples"] == 3))
        rgb = r["radiance"].mean(axis=0)
        self.assertTrue(np.all((rgb > 0.05) & (rgb < 1.0)), rgb)

    def test_adaptive_sampling(self):
        self.p.set_adaptive(max_relative_error=0.2, first_round_spp=2, round_spp=2, max_spp=8)
        try:
            r = self.p.predict()
        finally:
            self.p.adaptive_off()
        s = r["samples"]
        self.assertTrue(np.all((s >= 2) & (s <= 8) & (s % 2 == 0)))
        done = s < 8
        g, e = r["radiance"][:, 1], r["stderr"][:, 1]
        self.assertTrue(np.all(e[done] <= 0.2 * g[done] + 1e-7))
        self.assertGreater(s.max(), s.min())


class PrepareTest(unittest.TestCase):
    def test_prepare_writes_a_grid_a_predictor_reads(self):
        model = os.path.join(os.path.dirname(SCENE), "..", "meshes", "cube10.gltf")
        with tempfile.TemporaryDirectory() as d:
            out = os.path.join(d, "cube.vdb")
            r = printlight.prepare(model, out, voxel_mm=(0.25, 0.25, 0.25), extrude_mm=0.5, color=(0.8, 0.2, 0.2))
            self.assertTrue(os.path.exists(out))
            self.assertEqual(r["color_source"], "constant --color")
            self.assertGreater(r["printed_voxels"], 40 ** 3 - 1)
            self.assertGreater(r["shell_voxels"], 0)
            self.assertGreater(r["surface_voxels"], 6 * 38 * 38)
            with self.assertRaises(ValueError):
                printlight.prepare(model, os.path.join(d, "cube.png"))
            with self.assertRaises(RuntimeError):
                printlight.prepare(os.path.join(d, "missing.gltf"), os.path.join(d, "m.vdb"))
            self.assertFalse(os.path.exists(os.path.join(d, "m.vdb")))


if __name__ == "__main__":
    unittest.main(verbosity=2)
