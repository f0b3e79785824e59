#!/usr/bin/env python3
"""margins.py on hand-made records: each run's gap, the window of thresholds keeping every
decision, and against the graphs by construction the runs that have a threshold of their own and
the window shared by all (none when a contact of one run outscores a tie of another)."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(__file__), "margins.py")


class MarginsTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, self.folder)

    def write_run(self, name, scores, expected, threshold=0.06):
        """A record: graph.json (scores over arm 0 and pucks 1, 2; thresholded) and result.txt."""
        os.makedirs(os.path.join(self.folder, name))
        adjacency = [[int(i != j and s >= threshold) for j, s in enumerate(row)] for i, row in enumerate(scores)]
        graph = {"num_entities": 3, "threshold": threshold, "edge_scores": scores, "adjacency": adjacency}
        with open(os.path.join(self.folder, name, "graph.json"), "w") as f:
            json.dump(graph, f)
        with open(os.path.join(self.folder, name, "result.txt"), "w") as f:
            json.dump({"expected": expected}, f)

    def run_margins(self):
        """margins.py's output and its last line's summary."""
        out = subprocess.run([sys.executable, SCRIPT, self.folder], capture_output=True, text=True, check=True).stdout
        return out, json.loads(out.strip().splitlines()[-1])

    def test_a_contact_above_another_runs_tie_leaves_no_shared_threshold(self):
        # two pucks that only touch: their contact 0.07 is kept at 0.06, wrongly
        self.write_run("contact-s1", [[0, 0.9, 0.8], [0.01, 0, 0.07], [0.02, 0.07, 0]],
                       "action->0, 0->1, 0->2")
        # a rope 1 <-> 2 at 0.05 is cut at 0.06, wrongly; its next edge 0.01
        self.write_run("rope-s1", [[0, 0.5, 0.4], [0.01, 0, 0.05], [0.005, 0.05, 0]],
                       "action->0, 0->1, 0->2, 1->2, 2->1")
        out, summary = self.run_margins()
        # the decisions: gaps 0.07 / 0.02 = 3.5 and 0.4 / 0.05 = 8; all kept by a threshold
        # above the rope's 0.05 and up to the contact's 0.07
        self.assertAlmostEqual(summary["min_gap"], 3.5)
        self.assertAlmostEqual(summary["window_low"], 0.05)
        self.assertAlmostEqual(summary["window_high"], 0.07)
        # by construction: each run has its own (0.07-0.8 and 0.01-0.05), no shared one
        self.assertEqual(summary["exact_runs_possible"], 2)
        self.assertAlmostEqual(summary["exact_window_low"], 0.07)
        self.assertAlmostEqual(summary["exact_window_high"], 0.05)
        self.assertIn("2 of 2 runs have a threshold of their own", out)
        self.assertIn("a threshold shared by all: none", out)

    def test_a_tie_below_a_cut_edge_of_its_own_run_has_no_threshold(self):
        self.write_run("soft-spring-s1", [[0, 0.9, 0.8], [0.015, 0, 0.011], [0.01, 0.011, 0]],
                       "action->0, 0->1, 0->2, 1->2, 2->1")
        self.write_run("exact-s1", [[0, 0.9, 0.8], [0.01, 0, 0.2], [0.01, 0.2, 0]],
                       "action->0, 0->1, 0->2, 1->2, 2->1")
        out, summary = self.run_margins()
        self.assertEqual(summary["exact_runs_possible"], 1)
        self.assertIn("(not: soft-spring-s1)", out)

    def test_records_that_all_fit_share_a_window(self):
        self.write_run("a-s1", [[0, 0.9, 0.8], [0.01, 0, 0.02], [0.03, 0.02, 0]], "action->0, 0->1, 0->2")
        self.write_run("b-s1", [[0, 0.7, 0.3], [0.04, 0, 0.1], [0.01, 0.1, 0]],
                       "action->0, 0->1, 0->2, 1->2, 2->1")
        out, summary = self.run_margins()
        self.assertEqual(summary["exact_runs_possible"], 2)
        self.assertAlmostEqual(summary["exact_window_low"], 0.04)
        self.assertAlmostEqual(summary["exact_window_high"], 0.1)
        self.assertIn("a threshold shared by all: [0.0400, 0.1000]", out)


if __name__ == "__main__":
    unittest.main()
