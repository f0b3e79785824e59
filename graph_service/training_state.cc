#include "graph_service/training_state.h"

#include <algorithm>
#include <utility>

namespace srics::graph_service {

std::vector<nn::CheckpointSection> TrainingState::Save() const {
  nn::ByteWriter data_bytes, counters;
  data->Save(data_bytes);
  counters.Put<int32_t>(dropped);
  counters.Put<int32_t>(stable);
  // the refinement's (absent from states written before it existed)
  counters.Put<int32_t>(refine_cursor);
  counters.Put<int32_t>(refine_episodes);
  counters.Put<uint8_t>(refine_decided ? 1 : 0);
  std::vector<nn::CheckpointSection> sections = {{"graph.data", "", {}, data_bytes.Take()},
                                                 {"graph.service", "", {}, counters.Take()}};
  if (refine_data) {
    nn::ByteWriter refine;
    refine_data->Save(refine);
    sections.push_back({"graph.refine_data", "", {}, refine.Take()});
  }
  if (lowest_loss) {
    sections.push_back({"graph.lowest_loss", "", {}, graph_file::GraphToJson(*lowest_loss)});
  }
  if (trainer)
    for (nn::CheckpointSection& section : trainer->SaveState()) sections.push_back(std::move(section));
  return sections;
}

TrainingState TrainingState::Restore(const std::vector<nn::CheckpointSection>& sections, const std::string& path,
                                     const GraphDataset& empty, const config::GraphConfig& config,
                                     const RestoreOptions& options) {
  TrainingState state;
  state.data = std::make_unique<GraphDataset>(empty.EmptyCopy());
  nn::ByteReader data_bytes(nn::FindSection(sections, "graph.data", path).bytes, path + ": graph.data");
  state.data->Load(data_bytes);
  if (state.data->size() > config.episodes)
    throw nn::CheckpointError(path + ": " + std::to_string(state.data->size()) +
                              " episodes, the run's graph.episodes is " + std::to_string(config.episodes));
  nn::ByteReader counters(nn::FindSection(sections, "graph.service", path).bytes, path + ": graph.service");
  state.dropped = counters.Get<int32_t>();
  state.stable = counters.Get<int32_t>();
  if (!counters.done()) {
    state.refine_cursor = counters.Get<int32_t>();
    state.refine_episodes = counters.Get<int32_t>();
    state.refine_decided = counters.Get<uint8_t>() != 0;
  }
  if (const auto section = std::find_if(sections.begin(), sections.end(),
                                        [](const nn::CheckpointSection& s) { return s.name == "graph.refine_data"; });
      section != sections.end() && config.refine_after_publish) {
    state.refine_data = std::make_unique<GraphDataset>(state.data->ForTrainingEpisodes(options.refine_episode_steps));
    nn::ByteReader refine_bytes(section->bytes, path + ": graph.refine_data");
    state.refine_data->Load(refine_bytes);
    if (state.refine_cursor < 0 || state.refine_cursor >= std::max(1, state.refine_data->size()) ||
        state.refine_episodes < state.refine_data->size())
      throw nn::CheckpointError(path + ": the refinement's counters do not fit its " +
                                std::to_string(state.refine_data->size()) + " episodes");
  }
  if (const auto section = std::find_if(sections.begin(), sections.end(),
                                        [](const nn::CheckpointSection& s) { return s.name == "graph.lowest_loss"; });
      section != sections.end()) {
    try {
      state.lowest_loss = graph_file::GraphFromJson(section->bytes);
    } catch (const std::exception& e) {
      throw nn::CheckpointError(path + ": graph.lowest_loss: " + e.what());
    }
    if (state.lowest_loss->graph.num_entities != empty.graph_entities())
      throw nn::CheckpointError(path + ": graph.lowest_loss has " +
                                std::to_string(state.lowest_loss->graph.num_entities) + " entities, the data set " +
                                std::to_string(empty.graph_entities()));
  }
  const bool has_trainer =
      std::any_of(sections.begin(), sections.end(), [](const nn::CheckpointSection& s) { return s.name == "gnn"; });
  if (state.data->size() >= config.episodes) {
    state.data->Split(config.held_out_fraction, options.seed);
    state.trainer = std::make_unique<GnnTrainer>(config, *state.data, options.seed);
    state.trainer->SetContactRadii(options.contact_radius);
    if (has_trainer) state.trainer->LoadState(sections, path);
  }
  return state;
}

}  // namespace srics::graph_service
