#!/usr/bin/env python3
"""tests/bench_pair.py's arithmetic: JSON lines found, ratios pair by pair, medians."""
import importlib.util
import math
import os
import unittest

spec = importlib.util.spec_from_file_location("bench_pair", os.path.join(os.path.dirname(__file__), "bench_pair.py"))
bench_pair = importlib.util.module_from_spec(spec)
spec.loader.exec_module(bench_pair)


class BenchPairTest(unittest.TestCase):
    def test_last_json_line_wins_and_text_is_skipped(self):
        text = 'table\n{"a": 1}\nmore text\n{"a": 2, "b": "x"}\n{not json\n'
        self.assertEqual(bench_pair.last_json(text), {"a": 2, "b": "x"})
        self.assertIsNone(bench_pair.last_json("no json here\n[1, 2]\n"))

    def test_ratios_are_taken_pair_by_pair(self):
        base = [{"ms": 10.0, "name": "x"}, {"ms": 20.0, "name": "x"}, {"ms": 40.0, "name": "x"}]
        new = [{"ms": 9.0, "name": "y"}, {"ms": 30.0, "name": "y"}, {"ms": 36.0, "name": "y"}]
        table = bench_pair.pair_ratios(base, new)
        self.assertEqual(list(table), ["ms"])  # strings are not compared
        median_base, median_new, ratios, median_ratio = table["ms"]
        self.assertEqual((median_base, median_new), (20.0, 30.0))
        self.assertEqual(ratios, [0.9, 1.5, 0.9])
        # the median of the pairs' ratios (0.9), not the ratio of the medians (1.5)
        self.assertAlmostEqual(median_ratio, 0.9)

    def test_keys_missing_in_a_run_and_zero_bases(self):
        base = [{"a": 0.0, "b": 2.0, "flag": True}, {"a": 1.0, "b": 4.0, "flag": True}]
        new = [{"a": 5.0, "b": 3.0, "flag": False}, {"a": 3.0, "flag": False}]
        table = bench_pair.pair_ratios(base, new)
        self.assertEqual(list(table), ["a"])  # b is missing once, booleans are not numbers here
        self.assertEqual(table["a"][2], [3.0])  # the pair with base 0 has no ratio
        only = bench_pair.pair_ratios([{"a": 1, "c": 2}], [{"a": 2, "c": 2}], keys=["c", "z"])
        self.assertEqual(list(only), ["c"])
        self.assertTrue(math.isclose(only["c"][3], 1.0))

    def test_unpaired_runs_are_refused(self):
        with self.assertRaises(ValueError):
            bench_pair.pair_ratios([{"a": 1}], [])


if __name__ == "__main__":
    unittest.main()
