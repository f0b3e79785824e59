#!/usr/bin/env python3
"""pair_bars.py on hand-made records: a two-puck contact the evidence does not name is cut, a rope
it names is kept under the one threshold, a run without evidence keeps its recorded decisions, and
the scaled scores, gaps and tally are the ones computed by hand."""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(__file__), "pair_bars.py")

# two pucks (1, 2) that start moving at a distance 40 and 38 times, nearly always together: a tie
TIED = """onsets at a distance (per entity, nothing in reach: a tie's evidence): 0: 0 1: 40 2: 38
  ... while another object moves (i->j: j starts while i moves): 1->2: 37 2->1: 39
by construction: action->0, 0->1, 0->2, 1->2, 2->1
"""
# two pucks that only touch: once at a distance, never while the other moves
UNTIED = """onsets at a distance (per entity, nothing in reach: a tie's evidence): 0: 0 1: 1 2: 0
  ... while another object moves (i->j: j starts while i moves): none
by construction: action->0, 0->1, 0->2
"""


class PairBarsTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp()
        self.addCleanup(shutil.rmtree, self.folder)

    def write_run(self, name, pair_score, expected, evidence=None, scores=None):
        """A record read at 0.06 (arm 0 and pucks 1, 2 unless scores are given): graph.json,
        result.txt and evidence.txt."""
        run = os.path.join(self.folder, "records", name)
        os.makedirs(run)
        scores = scores or [[0, 0.9, 0.8], [0.01, 0, pair_score], [0.005, pair_score, 0]]
        graph = {"num_entities": len(scores), "action_entity": 0, "threshold": 0.06, "edge_scores": scores}
        with open(os.path.join(run, "graph.json"), "w") as f:
            json.dump(graph, f)
        with open(os.path.join(run, "result.txt"), "w") as f:
            json.dump({"expected": expected}, f)
        if evidence is not None:
            with open(os.path.join(run, "evidence.txt"), "w") as f:
                f.write(evidence)

    def run_bars(self, *extra):
        out = subprocess.run([sys.executable, SCRIPT, os.path.join(self.folder, "records"), *extra],
                             capture_output=True, text=True, check=True).stdout
        return out, json.loads(out.strip().splitlines()[-1])

    def test_the_evidence_sets_each_pairs_bar(self):
        self.write_run("contact-s1", 0.07, "action->0, 0->1, 0->2", UNTIED)
        self.write_run("rope-s1", 0.045, "action->0, 0->1, 0->2, 1->2, 2->1", TIED)
        out, summary = self.run_bars()
        self.assertEqual(summary["exact"], 2)
        self.assertEqual(summary["misses"], [])
        # contact: 0.07 * 0.06 / 0.12 = 0.035 cut; kept the arm's 0.8: gap 0.8 / 0.035
        self.assertIn("| contact-s1 | none | yes | 0.8000 | 0.0350 | 22.86 | 1.71 |", out)
        # rope: 0.045 * 0.06 / 0.02 = 0.135 kept; strongest cut the arm's 0.01 out of puck 1
        self.assertIn("| rope-s1 | 1-2 | yes | 0.1350 | 0.0100 | 13.50 | 2.25 |", out)
        # with the rope's bar at 0.05 it is cut (0.045 * 0.06 / 0.05 = 0.054)
        _, strict = self.run_bars("--tied", "0.05")
        self.assertEqual(strict["misses"], ["rope-s1"])

    def test_a_run_without_evidence_keeps_its_one_threshold(self):
        self.write_run("contact-s1", 0.07, "action->0, 0->1, 0->2")
        out, summary = self.run_bars()
        self.assertEqual(summary["without_evidence"], 1)
        self.assertEqual(summary["misses"], ["contact-s1"])
        self.assertIn("| contact-s1 | no evidence | no: 1->2 2->1 |", out)
        # found in an --evidence folder's <run>/log.txt instead
        os.makedirs(os.path.join(self.folder, "evidence", "contact-s1"))
        with open(os.path.join(self.folder, "evidence", "contact-s1", "log.txt"), "w") as f:
            f.write("[ 1.0s] collecting\n" + UNTIED)
        _, summary = self.run_bars("--evidence", os.path.join(self.folder, "evidence"))
        self.assertEqual((summary["without_evidence"], summary["exact"]), (0, 1))

    def test_a_record_the_service_read_with_its_bars_is_final(self):
        # scored 0.045 raw, 0.135 as the service published it: not scaled again (0.405)
        self.write_run("rope-s1", 0.135, "action->0, 0->1, 0->2, 1->2, 2->1",
                       TIED + "object pairs' bars: 0.02 for a pair tied by that evidence, 0.12 for any other "
                              "(the arm's edges 0.06)\n")
        out, summary = self.run_bars()
        self.assertEqual((summary["read_by_the_service"], summary["without_evidence"], summary["exact"]), (1, 0, 1))
        self.assertIn("| rope-s1 | read by the service | yes | 0.1350 | 0.0100 |", out)

    def test_a_log_without_the_graph_by_construction_takes_the_records(self):
        self.write_run("rope-s1", 0.045, "action->0, 0->1, 0->2, 1->2, 2->1", TIED.split("by construction")[0])
        out, summary = self.run_bars()
        self.assertEqual((summary["without_evidence"], summary["exact"]), (0, 1))
        self.assertIn("| rope-s1 | 1-2 | yes | 0.1350 |", out)

    def test_the_pair_share_cuts_the_scaled_scores(self):
        # pucks 1-2 named at 0.06 (scaled 0.18), a contact 2-3 at 0.14 (scaled 0.07, over the
        # threshold but under half the tie's 0.18: cut, as the service cuts after scaling)
        scores = [[0, 0.9, 0.8, 0.7], [0.01, 0, 0.06, 0], [0.005, 0.06, 0, 0.14], [0.004, 0, 0.14, 0]]
        evidence = ("onsets at a distance (per entity, nothing in reach: a tie's evidence): 0: 0 1: 40 2: 38 3: 0\n"
                    "  ... while another object moves (i->j: j starts while i moves): 1->2: 37 2->1: 39\n"
                    "by construction: action->0, 0->1, 0->2, 0->3, 1->2, 2->1\n")
        self.write_run("rope-s1", None, "action->0, 0->1, 0->2, 0->3, 1->2, 2->1", evidence, scores)
        _, summary = self.run_bars()
        self.assertEqual(summary["misses"], [])
        _, unshared = self.run_bars("--pair-share", "0")
        self.assertEqual(unshared["misses"], ["rope-s1"])

    def test_a_tied_bar_above_the_untied_one_is_refused(self):
        self.write_run("rope-s1", 0.045, "action->0, 0->1, 0->2, 1->2, 2->1", TIED)
        done = subprocess.run([sys.executable, SCRIPT, os.path.join(self.folder, "records"), "--tied", "0.2"],
                              capture_output=True, text=True)
        self.assertNotEqual(done.returncode, 0)
        self.assertIn("--tied", done.stderr)


if __name__ == "__main__":
    unittest.main()
