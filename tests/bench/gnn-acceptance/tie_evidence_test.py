#!/usr/bin/env python3
"""tie_evidence.py on a hand-written learn-graph log of two ties (1-2 and 3-4) and a free puck 5:
each pair's smaller count and smaller share, by hand."""
import importlib.util
import os
import unittest

spec = importlib.util.spec_from_file_location("tie_evidence", os.path.join(os.path.dirname(__file__), "tie_evidence.py"))
tie_evidence = importlib.util.module_from_spec(spec)
spec.loader.exec_module(tie_evidence)

LOG = """onsets at a distance (per entity, nothing in reach: a tie's evidence): 0: 0 1: 40 2: 50 3: 100 4: 80 5: 10
  ... while another object moves (i->j: j starts while i moves): 1->2: 48 2->1: 40 1->3: 20 3->1: 8 2->5: 6 3->4: 76 4->3: 95
by construction: action->0, 0->1, 0->2, 0->3, 0->4, 0->5, 1->2, 2->1, 3->4, 4->3
"""


class TieEvidenceTest(unittest.TestCase):
    def test_each_pair_has_its_rarer_ends_count_and_smaller_share(self):
        pairs = {(i, j): (tied, count, share) for i, j, tied, count, share in tie_evidence.pairs_of(LOG)}
        self.assertEqual(len(pairs), 10)  # five objects; the arm (0) is no object
        self.assertEqual(pairs[(1, 2)], (True, 40, min(40 / 40, 48 / 50)))
        self.assertEqual(pairs[(3, 4)], (True, 80, min(95 / 100, 76 / 80)))
        # 1 started while 3 moved 8 of 40 times, 3 while 1 moved 20 of 100: the smaller 0.2
        self.assertEqual(pairs[(1, 3)], (False, 40, 0.2))
        # 5 started 6 of 10 times while 2 moved, 2 never while 5 moved
        self.assertEqual(pairs[(2, 5)], (False, 10, 0.0))
        self.assertEqual(pairs[(4, 5)], (False, 10, 0.0))

    def test_no_evidence_line_no_pairs(self):
        self.assertIsNone(tie_evidence.pairs_of("by construction: action->0, 0->1\n"))
        self.assertEqual(tie_evidence.pairs_of(LOG.replace(
            LOG.splitlines()[1], "  ... while another object moves (i->j: j starts while i moves): none"))[0][4], 0.0)


if __name__ == "__main__":
    unittest.main()
