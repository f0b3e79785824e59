#!/usr/bin/env python3
"""lowest_loss.py on a hand-written learn-graph log: the settled evaluations only, the lowest
held-out loss (the first of equals), the published graph, the expected one."""
import importlib.util
import os
import unittest

spec = importlib.util.spec_from_file_location("lowest_loss", os.path.join(os.path.dirname(__file__), "lowest_loss.py"))
lowest_loss = importlib.util.module_from_spec(spec)
spec.loader.exec_module(lowest_loss)

LOG = """onsets at a distance (per entity, nothing in reach: a tie's evidence): 0: 0 1: 70 2: 60
[  600.0s] training   episodes 1000/1000 (dropped 0) updates 3000 held-out 1e-05 (no-motion 0.0005) stable 0  action->0
[  700.0s] training   episodes 1000/1000 (dropped 0) updates 3500 held-out 8.3e-05 (no-motion 0.0005) stable 0  action->0, 1->2, 2->1
[  750.0s] training   episodes 1000/1000 (dropped 0) updates 4000 held-out 8.9e-05 (no-motion 0.0005) stable 0  action->0
[  800.0s] training   episodes 1000/1000 (dropped 0) updates 4500 held-out 8.3e-05 (no-motion 0.0005) stable 0  action->0, 0->1
[  850.0s] training   episodes 1000/1000 (dropped 0) updates 5000 held-out 9e-05 (no-motion 0.0005) stable 0  action->0
[  851.0s] published  episodes 1000/1000 (dropped 0) updates 5000 held-out 9e-05 (no-motion 0.0005) stable 0  action->0
published graph version 1: action->0
by construction: action->0, 1->2, 2->1 (differs)
"""


class LowestLossTest(unittest.TestCase):
    def test_the_settled_evaluation_of_the_lowest_loss(self):
        # 3000's loss is lower but not settled; 3500 and 4500 tie: the first is kept
        self.assertEqual(lowest_loss.outcomes(LOG, 3000), ("action->0, 1->2, 2->1", "action->0", "action->0, 1->2, 2->1"))
        # counted from 0 the unsettled 3000 wins
        self.assertEqual(lowest_loss.outcomes(LOG, 0)[2], "action->0")

    def test_last_is_the_last_evaluation_whichever_graph_the_run_published(self):
        # a run with graph.publish: lowest_held_out_loss published 3500's graph
        published_lowest = LOG.replace("published graph version 1: action->0\n",
                                       "published graph version 1: action->0, 1->2, 2->1\n")
        self.assertEqual(lowest_loss.outcomes(published_lowest, 3000),
                         ("action->0, 1->2, 2->1", "action->0", "action->0, 1->2, 2->1"))

    def test_a_run_without_a_published_graph_or_settled_evaluations_is_left_out(self):
        self.assertIsNone(lowest_loss.outcomes(LOG.replace("published graph version 1", "stopped"), 3000))
        self.assertIsNone(lowest_loss.outcomes(LOG, 5000))


if __name__ == "__main__":
    unittest.main()
