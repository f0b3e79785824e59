#pragma once
// Two studies of trained policies that `srics eval` plays over several run folders (each
// run's final policy, checkpoint.srics, never best.srics; each evaluation's own files in
// OUT/raw/, the tables by deploy/analysis/eval_studies.h):
//   --cross-protocol  every run under both protocols ("depth": the graph's subgoals in depth
//                     order, as SRICS evaluates; "random": every entity, random order, as SMORL
//                     evaluates) on the goals of each --goal-sets seed: OUT/cross-eval.csv, .md
//   --seen / --unseen every run and the passive baseline on each object combination (catalogue
//                     ids of the present pucks), the held-out one too: OUT/seen-unseen.csv, .md
// Progress goes to stderr, one line per evaluation.

#include "deploy/eval/eval.h"

namespace srics::eval {

// Whether `args` asks for a study (several runs) rather than one evaluation.
bool IsEvalStudy(const EvalArgs& args);

// Plays the study `args` asks for; returns 0. Throws like Eval (std::invalid_argument for a
// run folder without checkpoint.srics and config.yaml, before anything is played).
int RunEvalStudy(const EvalArgs& args);

}  // namespace srics::eval
