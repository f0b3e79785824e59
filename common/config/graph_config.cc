#include "common/config/sections.h"

namespace srics::config {

void ParseGraph(YamlSection s, GraphConfig* out) {
  s.ReadBool("ground_truth", &out->ground_truth);
  s.ReadString("file", &out->file);
  s.ReadInt("episodes", &out->episodes, 1, 1 << 24);
  s.ReadInt("episode_steps", &out->episode_steps, 2, 100000);
  s.ReadDouble("held_out_fraction", &out->held_out_fraction, 0, 0.9);
  s.ReadInt("hidden_dim", &out->hidden_dim, 1, 4096);
  s.ReadInt("mlp_hidden", &out->mlp_hidden, 1, 8192);
  s.ReadInt("window", &out->window, 2, 100000);
  s.ReadInt("batch_windows", &out->batch_windows, 1, 1 << 20);
  s.ReadDouble("learning_rate", &out->learning_rate, 1e-12, 1);
  s.ReadDouble("delta_scale", &out->delta_scale, 1e-6, 1e6);
  s.ReadBool("edge_node_inputs", &out->edge_node_inputs);
  s.ReadBool("normalize_per_entity", &out->normalize_per_entity);
  s.ReadBool("standardize_inputs", &out->standardize_inputs);
  s.ReadDouble("edge_relative_scale", &out->edge_relative_scale, 0, 1e3);
  s.ReadBool("use_adam", &out->use_adam);
  s.ReadDouble("edge_prior", &out->edge_prior, 1e-6, 1 - 1e-6);
  s.ReadDouble("kl_weight", &out->kl_weight, 0, 1e6);
  s.ReadInt("warmup_updates", &out->warmup_updates, 0, 1 << 30);
  s.ReadInt("kl_ramp_updates", &out->kl_ramp_updates, 0, 1 << 30);
  s.ReadDouble("gumbel_temperature", &out->gumbel_temperature, 1e-3, 100);
  s.ReadEnum("readout", &out->readout, {{"cut", GraphReadout::kCut}, {"mean_weight", GraphReadout::kMeanWeight}});
  s.ReadDouble("threshold", &out->threshold, 0, 1);
  s.ReadEnum("object_edges", &out->object_edges,
             {{"apart", ObjectEdgeReadout::kApart}, {"every_step", ObjectEdgeReadout::kEveryStep}});
  s.ReadDouble("contact_margin_m", &out->contact_margin_m, 0, 1);
  s.ReadDouble("object_contact_margin_m", &out->object_contact_margin_m, 0, 1);
  s.ReadDouble("cut_threshold", &out->cut_threshold, 0, 1);
  s.ReadDouble("static_variance_fraction", &out->static_variance_fraction, 0, 1);
  s.ReadBool("reciprocal_object_edges", &out->reciprocal_object_edges);
  s.ReadDouble("object_pair_share", &out->object_pair_share, 0, 1);
  // recorded in the resolved settings only when given: every config written before the key
  // resolves to the same settings as before, so a run continued with this binary is no change
  if (s.Has("object_ties"))
    s.ReadEnum("object_ties", &out->object_ties,
               {{"two_way", ObjectTies::kTwoWay}, {"one_way", ObjectTies::kOneWay}, {"joint", ObjectTies::kJoint}});
  // always recorded since its default changed (config::EarlierDefaults)
  s.ReadEnum("publish", &out->publish,
             {{"last", GraphPublish::kLast}, {"lowest_held_out_loss", GraphPublish::kLowestHeldOutLoss}});
  s.ReadDouble("gate_logit_decay", &out->gate_logit_decay, 0, 1e3);
  s.ReadDouble("onset_loss_weight", &out->onset_loss_weight, 0, 1e3);
  s.ReadDouble("onset_motion_m", &out->onset_motion_m, 0, 1);
  // always recorded since their defaults changed (a record without them ran with the tie KL
  // off: config::EarlierDefaults)
  s.ReadDouble("tie_evidence_per_episode", &out->tie_evidence_per_episode, 0, 1e3);
  s.ReadDouble("tie_kl_factor", &out->tie_kl_factor, 1e-6, 1);
  s.ReadDouble("tie_evidence_share", &out->tie_evidence_share, 0, 1);
  s.ReadDouble("tied_pair_threshold", &out->tied_pair_threshold, 0, 1);
  s.ReadDouble("untied_pair_threshold", &out->untied_pair_threshold, 0, 1);
  s.ReadBool("restart_adam_after_warmup", &out->restart_adam_after_warmup);
  s.ReadDouble("adam_beta2_after_warmup", &out->adam_beta2_after_warmup, 0, 1 - 1e-9);
  s.ReadBool("hard_edges", &out->hard_edges);
  s.ReadInt("max_updates", &out->max_updates, 1, 1 << 30);
  s.ReadInt("min_updates", &out->min_updates, 0, 1 << 30);
  s.ReadInt("eval_every_updates", &out->eval_every_updates, 1, 1 << 30);
  s.ReadInt("stable_evaluations", &out->stable_evaluations, 1, 1 << 20);
  s.ReadInt("eval_chunk_episodes", &out->eval_chunk_episodes, 1, 1 << 20);
  s.ReadInt("max_skipped_updates_in_a_row", &out->max_skipped_updates_in_a_row, 0, 1 << 30);
  s.ReadBool("refine_after_publish", &out->refine_after_publish);
  s.ReadDouble("refine_share", &out->refine_share, 0, 1);
  s.ReadInt("refine_updates_per_episode", &out->refine_updates_per_episode, 0, 1 << 20);
  if (out->refine_after_publish && (out->ground_truth || !out->file.empty()))
    s.FailRule("refine_after_publish", "needs a learned graph (graph.ground_truth and graph.file publish a fixed one)");
  if (out->refine_after_publish && (out->refine_share <= 0 || out->refine_updates_per_episode <= 0))
    s.FailRule("refine_after_publish", "needs refine_share and refine_updates_per_episode above 0");
  if (out->object_ties == ObjectTies::kOneWay && (out->ground_truth || !out->file.empty()))
    s.FailRule("object_ties",
               "one_way orients a learned graph's ties; graph.ground_truth and graph.file publish theirs as they are "
               "(set graph.object_ties=two_way or joint with them)");
  if ((out->tied_pair_threshold > 0) != (out->untied_pair_threshold > 0))
    s.FailRule("tied_pair_threshold",
               "and untied_pair_threshold are both above 0 (the evidence sets each object pair's bar) or both 0 (off)");
  if (out->tied_pair_threshold > out->untied_pair_threshold)
    s.FailRule("tied_pair_threshold",
               "must not exceed untied_pair_threshold: evidence of a tie lowers an object pair's bar, never raises it");
  if (out->pair_bars_on() && out->threshold <= 0)
    s.FailRule("threshold",
               "must be above 0 with the object pairs' bars (tied_pair_threshold, untied_pair_threshold): "
               "each pair's score is scaled by threshold / its bar");
  if (out->ground_truth && !out->file.empty())
    s.FailRule("file", "and graph.ground_truth both name the graph to use: set one");
  if (out->min_updates > out->max_updates)
    s.FailRule("min_updates", "must not exceed max_updates (" + std::to_string(out->max_updates) + ")");
  const int held_out = static_cast<int>(out->episodes * out->held_out_fraction + 0.5);
  if (held_out < 1 || out->episodes - held_out < 1)
    s.FailRule("held_out_fraction", "must leave at least one training and one held-out episode");
  if (out->window > out->episode_steps)
    s.FailRule("window", "must not exceed episode_steps (" + std::to_string(out->episode_steps) + ")");
  s.Finish();
}

}  // namespace srics::config
