#pragma once
// The statistics of the project's tables, in one place: mean, sample standard deviation
// (n - 1), min and max of a list of values, and their text as the tables print them.

#include <string>
#include <vector>

namespace srics::analysis {

struct Spread {
  double mean = 0, std = 0, min = 0, max = 0;  // std: sample standard deviation, 0 for one value
  int n = 0;
};
Spread SpreadOf(const std::vector<double>& values);

// The values b[i] - a[i] of two lists of one length (a paired difference: the same runs under
// two conditions). Throws std::invalid_argument when the lengths differ.
std::vector<double> Differences(const std::vector<double>& a, const std::vector<double>& b);

// `v` with `digits` decimals ("0.125"); with a sign when `sign` ("+0.125", "-0.010").
std::string Format(double v, int digits = 3, bool sign = false);
// "mean ± sd" with `digits` decimals, "-" without values.
std::string MeanStd(const Spread& s, int digits = 3, bool sign = false);

}  // namespace srics::analysis
