#pragma once
// Figures with gnuplot: quoting text for its scripts, running a script, and the learning curve
// of one run folder that `srics run` draws when a run ends.

#include <string>

namespace srics::analysis {

// `text` for inside a gnuplot single-quoted string (quotes doubled).
std::string GnuplotQuote(const std::string& text);

// Runs gnuplot on a script; false with *error (its output) when it fails or is missing.
bool RunGnuplot(const std::string& script_path, std::string* error);

// Draws <dir>/curve.png (avg object distance and avg distance vs env steps, the passive
// policy's values as horizontal lines) and <dir>/subgoal_success.png from <dir>/eval.csv
// with gnuplot. Also writes <dir>/curve.dat (the plotted points). Returns false with a
// reason in *error when there is nothing to plot, gnuplot is missing or fails.
bool PlotEvalCurves(const std::string& dir, const std::string& title, std::string* error);

}  // namespace srics::analysis
