# SPDX-License-Identifier: Apache-2.0
"""scripts/error_by_variance.py: bins by stated variance, keeps a repeated row's first, says which line is bad."""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(__file__), "..", "..", "scripts", "error_by_variance.py")
HEADER = "scene,t,view,object,x,y,z,cov_xx,cov_xy,cov_xz,cov_yy,cov_yz,cov_zz,method\n"


def estimate(t, z, variance, view="a"):
    return f"s,{t},{view},o,0,0,{z},1,0,0,1,0,{variance},ours-l\n"


class ErrorByVariance(unittest.TestCase):
    def run_script(self, truth, estimates, *args):
        with tempfile.TemporaryDirectory() as folder:
            truth_path, estimates_path = os.path.join(folder, "truth.csv"), os.path.join(folder, "est.csv")
            with open(truth_path, "w") as f:
                f.write("scene,t,object,x,y,z\n" + truth)
            with open(estimates_path, "w") as f:
                f.write(HEADER + estimates)
            return subprocess.run([sys.executable, SCRIPT, truth_path, estimates_path, *args],
                                  capture_output=True, text=True), estimates_path

    def test_bins_by_stated_variance(self):
        truth = "".join(f"s,{t},o,0,0,0\n" for t in range(5))
        # Errors 1, 1 (stated 1: right) and 4, 4 (stated 4: four times too small); a second row of
        # time 0 from another view is the same estimate again and is not counted; time 9 has no truth.
        estimates = (estimate(0, 1, 1) + estimate(0, 3, 1, view="b") + estimate(1, -1, 1) + estimate(2, 4, 4) +
                     estimate(3, -4, 4) + estimate(9, 0, 1))
        result, _ = self.run_script(truth, estimates, "--axis", "z", "--bins", "2")
        self.assertEqual(result.returncode, 0, result.stderr)
        rows = [line for line in result.stdout.splitlines() if line.startswith("| 1 ") or line.startswith("| 2 ")]
        self.assertEqual(rows, ["| 1 | 2 | 1.00e+00 | 1.00e+00 | 1.00 |", "| 2 | 2 | 4.00e+00 | 1.60e+01 | 4.00 |"])

    def test_names_the_bad_line(self):
        result, path = self.run_script("s,0,o,0,0,0\n", estimate(0, 1, 1) + "s,zero,a,o,0,0,0,1,0,0,1,0,1,x\n")
        self.assertNotEqual(result.returncode, 0)
        self.assertIn(f"{path}:3:", result.stderr)


if __name__ == "__main__":
    unittest.main()
