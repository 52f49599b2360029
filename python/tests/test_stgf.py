# SPDX-License-Identifier: Apache-2.0
"""The Python module against hand-checkable cases and against the CLI on the same files."""

import os
import subprocess
import tempfile
import unittest

import numpy as np

import stgf


def two_views(n_steps=10, dt=0.2):
    """An object walking 1 m/s along x seen by two views: exact z, R = 0.01 I."""
    time = np.repeat(np.arange(n_steps) * dt, 2)
    view = ["a", "b"] * n_steps
    z = np.stack([time, np.zeros_like(time), np.zeros_like(time)], axis=1)
    R = np.repeat((0.01 * np.eye(3))[None], len(time), axis=0)
    return time, view, z, R


class TestModule(unittest.TestCase):
    def test_version_and_methods(self):
        self.assertTrue(stgf.__version__.startswith("0.2"))
        self.assertEqual(stgf.method_names(), ["aom", "wls", "mmt", "sttp", "ours-l", "ours"])


class TestFilter(unittest.TestCase):
    def test_two_views_at_one_time_weigh_by_information(self):
        f = stgf.Filter()
        est = f.fuse(time=[0.0, 0.0], view=["a", "b"], object="o",
                     z=[[0.0, 0.0, 0.0], [4.0, 0.0, 0.0]], R=[np.eye(3), 3 * np.eye(3)])
        # A new track starts at the information-weighted mean: x = (0·1 + 4·⅓) / (1 + ⅓) = 1.
        np.testing.assert_allclose(est["mean"][0], [1.0, 0.0, 0.0], atol=1e-9)
        np.testing.assert_allclose(est["covariance"][0], 0.75 * np.eye(3), atol=1e-9)
        np.testing.assert_array_equal(est["mean"][0], est["mean"][1])

    def test_streaming_in_pieces_equals_one_call(self):
        time, view, z, R = two_views()
        whole = stgf.Filter().fuse(time, view, "o", z, R)
        f = stgf.Filter()
        pieces = [f.fuse(time[k:k + 1], view[k:k + 1], "o", z[k:k + 1], R[k:k + 1]) for k in range(len(time))]
        # One message per view: a time's second view refines what the first one gave.
        np.testing.assert_allclose(np.concatenate([p["mean"] for p in pieces])[1::2], whole["mean"][1::2], atol=1e-12)
        self.assertEqual(whole["mean"].shape, (len(time), 3))
        self.assertEqual(whole["covariance"].shape, (len(time), 3, 3))
        self.assertLess(np.abs(whole["mean"] - z).max(), 0.02)

    def test_late_message_is_fused_in_place(self):
        time, view, z, R = two_views()

        def feed(order):
            f = stgf.Filter()
            last = None
            for k in order:
                last = f.fuse(time[k:k + 1], view[k:k + 1], "o", z[k:k + 1], R[k:k + 1])
            return f, last

        in_order, expected = feed(range(len(time)))
        order = list(range(len(time)))
        order[4], order[6] = order[6], order[4]  # view a at t=0.4 arrives after t=0.6
        late, got = feed(order)
        # The late message is fused in its place in time (one more rewind), none is left out, and
        # the end state is the in-order one.
        self.assertGreater(late.rewinds, in_order.rewinds)
        # Rows 5 and 4 came after row 6, of a later time.
        self.assertEqual((in_order.late_rows, late.late_rows), (0, 2))
        self.assertEqual(late.late_measurements, 0)
        np.testing.assert_allclose(got["mean"], expected["mean"], atol=1e-9)
        np.testing.assert_allclose(got["covariance"], expected["covariance"], atol=1e-12)

    def test_gate_leaves_out_a_gross_error_and_says_so(self):
        time, view, z, R = two_views()
        with tempfile.TemporaryDirectory() as folder:
            config = os.path.join(folder, "gate.yaml")
            with open(config, "w") as file:
                file.write("ours:\n  gate: true\n")
            f = stgf.Filter(config=config)
        f.fuse(time, view, "o", z, R)
        # Both views at one later time, one of them 10 m off: the gate keeps it out.
        t = float(time[-1]) + 0.1
        good = z[-1] + np.array([0.1, 0.0, 0.0])
        out = f.fuse([t, t], ["a", "b"], "o", np.stack([good, good + [10.0, 0.0, 0.0]]), R[:2])
        self.assertLess(np.abs(out["mean"][0] - good).max(), 0.2)
        gating = f.gating
        self.assertEqual(gating["b"]["gated"] + gating["a"]["gated"], 1)
        self.assertGreaterEqual(gating["b"]["checked"], 1)
        self.assertEqual(f.refilters, 0)  # one gross error is no faulty view: nothing to go back for

    def test_the_other_views_outvote_a_gross_error_and_say_so(self):
        # With offsets estimated (a registration prior given) and no gate: three views at one time, one
        # 10 m off, is fused with its noise scaled up (design §1.12) and counted.
        with tempfile.TemporaryDirectory() as folder:
            config = os.path.join(folder, "offsets.yaml")
            with open(config, "w") as file:
                file.write("ours:\n  registration_translation_sigma_m: 0.1\n  registration_noise_ratio: 0.5\n")
            f = stgf.Filter(config=config)
        good = np.array([1.0, 2.0, 0.0])
        z = np.stack([good, good + [10.0, 0.0, 0.0], good + [0.02, 0.0, 0.0]])
        out = f.fuse([0.0] * 3, ["a", "b", "c"], "o", z, np.stack([0.01 * np.eye(3)] * 3))
        self.assertLess(np.abs(out["mean"][0] - good).max(), 0.3)
        self.assertEqual(f.gating["b"]["down_weighted"], 1)
        self.assertNotIn("a", f.gating)

    def test_motion_fallback_is_reported(self):
        # Without a model the filter's motion model is constant velocity already: nothing to switch to.
        # With `motion_fallback: always` the filter says it follows constant velocity.
        f = stgf.Filter()
        f.fuse([0.0, 0.1, 0.2], ["a", "a", "a"], "o", np.array([[0.0, 0, 0], [0.1, 0, 0], [0.2, 0, 0]]),
               np.stack([0.01 * np.eye(3)] * 3))
        self.assertEqual(f.motion, "model")
        with tempfile.TemporaryDirectory() as folder:
            config = os.path.join(folder, "c.yaml")
            with open(config, "w") as file:
                file.write("ours:\n  motion_fallback: always\n")
            self.assertEqual(stgf.Filter(config=config).motion, "constant-velocity")

    def test_registration_prior_scales_to_the_views_offsets(self):
        # Six views whose offsets are five times the prior's σ (0.05 m): the prior's scale κ_t, learned
        # from their disagreements, comes out near 25; with adaptation off it stays 1. The prior has no
        # offset in units of the noise (α = 0), so κ_n is κ_t.
        rng = np.random.default_rng(4)
        offsets = 0.25 * rng.standard_normal((6, 3))
        offsets[:, 2] = 0.0
        time, view, obj, z = [], [], [], []
        for k in range(30):
            for i in range(4):
                for v in range(6):
                    time.append(0.1 * k)
                    view.append(f"v{v}")
                    obj.append(f"o{i}")
                    z.append(np.array([3.0 * i + 0.1 * k, float(i), 0.0]) + offsets[v] + 0.01 * rng.standard_normal(3))
        R = np.repeat((1e-4 * np.eye(3))[None], len(time), axis=0)
        scales = {}
        for adapt in ("true", "false"):
            with tempfile.TemporaryDirectory() as folder:
                config = os.path.join(folder, "prior.yaml")
                with open(config, "w") as file:
                    file.write("ours:\n  registration_translation_sigma_m: [0.05, 0.05, 0.0]\n"
                               f"  registration_noise_ratio: 0.0\n  adapt_registration_prior: {adapt}\n")
                f = stgf.Filter(config=config)
            self.assertEqual(f.registration_prior_scales, (1.0, 1.0))
            f.fuse(time, view, obj, np.array(z), R)
            scales[adapt] = f.registration_prior_scales
            offset = f.registration_offset("v0")  # (t, δ, ε): no δ or ε without their priors
            self.assertEqual(offset.shape, (7,))
            self.assertEqual(offset[3:].tolist(), [0.0] * 4)
            self.assertGreater(np.abs(offset[:2]).max(), 0.0)
        self.assertGreater(scales["true"][0], 8.0)
        self.assertLess(scales["true"][0], 80.0)
        self.assertEqual(scales["true"][1], scales["true"][0])
        self.assertEqual(scales["false"], (1.0, 1.0))

    def test_bad_arrays_raise_value_error_naming_the_row(self):
        f = stgf.Filter()
        with self.assertRaisesRegex(ValueError, r"z has shape \(2, 2\) where \(2, 3\) was expected"):
            f.fuse([0.0, 0.0], ["a", "b"], "o", np.zeros((2, 2)), np.repeat(np.eye(3)[None], 2, axis=0))
        bad = np.repeat(np.eye(3)[None], 2, axis=0)
        bad[1] = -np.eye(3)
        with self.assertRaisesRegex(ValueError, r"measurement 1: .*positive definite"):
            f.fuse([0.0, 0.0], ["a", "b"], "o", np.zeros((2, 3)), bad)
        with self.assertRaisesRegex(ValueError, "view has 1 entries for 2 measurements"):
            f.fuse([0.0, 0.0], ["a"], "o", np.zeros((2, 3)), np.repeat(np.eye(3)[None], 2, axis=0))
        with self.assertRaisesRegex(ValueError, "measurement 0: time is not finite"):
            f.fuse([np.nan], ["a"], "o", np.zeros((1, 3)), np.eye(3)[None])
        with self.assertRaisesRegex(ValueError, r"sensor_position has shape \(1, 2\) where \(1, 3\) was expected"):
            f.fuse([0.0], ["a"], "o", np.zeros((1, 3)), np.eye(3)[None], sensor_position=np.zeros((1, 2)))
        with self.assertRaisesRegex(ValueError, "measurement 0: sensor_position is not finite"):
            f.fuse([0.0], ["a"], "o", np.zeros((1, 3)), np.eye(3)[None], sensor_position=np.full((1, 3), np.nan))

    def test_missing_model_is_an_input_error(self):
        with self.assertRaisesRegex(stgf.InputError, "/nonexistent/model.pt"):
            stgf.Filter("/nonexistent/model.pt")
        self.assertTrue(issubclass(stgf.InputError, ValueError))


class TestFilesAndMethods(unittest.TestCase):
    """run/evaluate on files give what the CLI gives on the same files."""

    @classmethod
    def setUpClass(cls):
        cls.directory = tempfile.TemporaryDirectory()
        cls.dir = cls.directory.name
        cls.cli = os.environ["STGF_TEST_BINARY"]
        subprocess.run([cls.cli, "dataset", "mpl", "--out", os.path.join(cls.dir, "mpl"), "--train", "2", "--val", "1",
                        "--test", "2", "--steps", "10", "--pedestrians", "3", "-q"], check=True)
        cls.measurements = os.path.join(cls.dir, "mpl", "test", "measurements.csv")
        cls.truth = os.path.join(cls.dir, "mpl", "test", "truth.csv")

    @classmethod
    def tearDownClass(cls):
        cls.directory.cleanup()

    def test_read_measurements(self):
        m = stgf.read_measurements(self.measurements)
        n = len(m["time"])
        self.assertGreater(n, 0)
        self.assertEqual(m["z"].shape, (n, 3))
        self.assertEqual(m["R"].shape, (n, 3, 3))
        self.assertEqual(len(m["view"]), n)
        self.assertEqual(m["line"][0], 2)

    def test_wls_matches_the_cli_and_evaluation_matches_metrics(self):
        cli_out = os.path.join(self.dir, "wls-cli.csv")
        py_out = os.path.join(self.dir, "wls-py.csv")
        subprocess.run([self.cli, "run", "--method", "wls", "--measurements", self.measurements, "--out", cli_out, "-q"],
                       check=True)
        estimates = stgf.run_file("wls", self.measurements, py_out)
        with open(cli_out) as a, open(py_out) as b:
            self.assertEqual(a.read(), b.read())
        scores = stgf.evaluate(self.truth, [py_out])
        self.assertEqual(scores[0]["method"], "wls")
        # The same DE from the array metrics, matching rows to truth by (scene, t, object).
        m = stgf.read_measurements(self.measurements)
        t = stgf.read_truth(self.truth)
        index = {(s, round(time, 6), o): k for k, (s, time, o) in enumerate(zip(t["scene"], t["time"], t["object"]))}
        truth = np.array([t["position"][index[(s, round(time, 6), o)]]
                          for s, time, o in zip(m["scene"], m["time"], m["object"])])
        direct = stgf.metrics(estimates["mean"], estimates["covariance"], truth)
        self.assertEqual(direct["rows"], scores[0]["rows"])
        self.assertAlmostEqual(direct["de"], scores[0]["de"], places=8)  # the CSV rounds
        self.assertAlmostEqual(direct["nees_mean"], scores[0]["nees_mean"], places=5)
        self.assertAlmostEqual(direct["nees_horizontal_mean"], scores[0]["nees_horizontal_mean"], places=5)
        self.assertAlmostEqual(direct["nees_vertical_mean"], scores[0]["nees_vertical_mean"], places=5)
        # The error by stated variance: the rows binned by the octave of P_zz, each bin's mean r_z².
        variances = estimates["covariance"][:, 2, 2]
        squared = (estimates["mean"][:, 2] - truth[:, 2]) ** 2
        octaves = np.floor(np.log2(variances))
        bins = scores[0]["by_variance"]["z"]
        self.assertEqual(sum(b["rows"] for b in bins), scores[0]["rows"])
        self.assertEqual([b["variance_from"] for b in bins], [2.0 ** k for k in sorted(set(octaves))])
        for b in bins:
            in_bin = octaves == np.log2(b["variance_from"])
            self.assertEqual(b["rows"], int(in_bin.sum()))
            self.assertAlmostEqual(b["mean_squared_error"], squared[in_bin].mean(), places=8)

    def test_learned_method_without_a_model_uses_the_general_model(self):
        shipped = stgf.general_model()
        self.assertEqual(shipped.metadata["input"], "fused")
        self.assertEqual(stgf.run("ours", self.measurements, model=shipped)["mean"].tolist(),
                         stgf.run("ours", self.measurements)["mean"].tolist())
        # sttp's model learns from one view's raw measurements: the general model is not one.
        with self.assertRaisesRegex(ValueError, "method sttp needs --model"):
            stgf.run("sttp", self.measurements)
        with self.assertRaisesRegex(ValueError, "unknown method 'nope'"):
            stgf.run("nope", self.measurements)

    def test_bad_file_names_file_and_line(self):
        path = os.path.join(self.dir, "bad.csv")
        with open(path, "w") as f:
            f.write("scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz\n")
            f.write("s,0,v,o,1,2,oops,1,0,0,1,0,1\n")
        with self.assertRaisesRegex(stgf.InputError, r"bad\.csv:2:"):
            stgf.read_measurements(path)


@unittest.skipUnless(os.environ.get("STGF_TEST_TRAIN", "1") == "1", "training disabled")
class TestLearned(unittest.TestCase):
    """A model trained by the CLI drives ours in Python exactly as in the CLI."""

    def test_ours_matches_the_cli(self):
        with tempfile.TemporaryDirectory() as d:
            cli = os.environ["STGF_TEST_BINARY"]
            bench = os.path.join(d, "mpl")
            subprocess.run([cli, "dataset", "mpl", "--out", bench, "--train", "3", "--val", "2", "--test", "2",
                            "--steps", "10", "--pedestrians", "3", "-q"], check=True)
            model_path = os.path.join(d, "model.pt")
            subprocess.run([cli, "train", "--benchmark", bench, "--out", model_path, "--epochs", "1", "--threads", "1",
                            "-q"], check=True)
            measurements = os.path.join(bench, "test", "measurements.csv")
            cli_out = os.path.join(d, "ours-cli.csv")
            subprocess.run([cli, "run", "--method", "ours", "--model", model_path, "--measurements", measurements,
                            "--out", cli_out, "-q"], check=True)
            model = stgf.load_model(model_path)
            self.assertEqual(model.metadata["input"], "fused")
            self.assertEqual(model.process_noise(0.1).shape, (3, 3))
            py_out = os.path.join(d, "ours-py.csv")
            stgf.run_file("ours", measurements, py_out, model=model)
            with open(cli_out) as a, open(py_out) as b:
                self.assertEqual(a.read(), b.read())
            # The streaming filter, fed scene by scene, gives the same estimates as a run whose scenes
            # each learn Q's scales alone (by default a run's later scenes start from its earlier ones').
            per_scene = os.path.join(d, "per-scene.yaml")
            with open(per_scene, "w") as f:
                f.write("ours:\n  process_noise_scale: per-scene\n")
            per_scene_out = os.path.join(d, "ours-per-scene.csv")
            stgf.run_file("ours", measurements, per_scene_out, model=model, config=per_scene)
            m = stgf.read_measurements(measurements)
            batch = stgf.read_estimates(per_scene_out)
            for scene in sorted(set(m["scene"])):
                rows = [k for k, s in enumerate(m["scene"]) if s == scene]
                f = stgf.Filter(model)
                est = f.fuse(m["time"][rows], [m["view"][k] for k in rows], [m["object"][k] for k in rows],
                             m["z"][rows], m["R"][rows], sensor_position=m["sensor_position"][rows])
                np.testing.assert_allclose(est["mean"], batch["mean"][rows], atol=1e-6)


if __name__ == "__main__":
    unittest.main()
