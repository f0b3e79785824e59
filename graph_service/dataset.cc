#include "graph_service/dataset.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "common/links/links.h"

namespace srics::graph_service {
namespace {

// every kind list, one after the other (one list: itself, the checkpoint format of before)
std::vector<uint16_t> FlatKinds(const std::vector<std::vector<uint16_t>>& sets) {
  std::vector<uint16_t> flat;
  for (const auto& set : sets) flat.insert(flat.end(), set.begin(), set.end());
  return flat;
}

}  // namespace

GraphDataset::GraphDataset(const rl::EntityLayout& layout, std::vector<uint16_t> entity_kinds, int action_dim,
                           int episode_steps)
    : layout_(layout),
      kind_sets_{std::move(entity_kinds)},
      by_identity_(false),
      action_dim_(action_dim),
      steps_(episode_steps) {
  CheckShape();
}

GraphDataset::GraphDataset(const rl::EntityLayout& layout, std::vector<std::vector<uint16_t>> kind_sets, int action_dim,
                           int episode_steps)
    : layout_(layout),
      kind_sets_(std::move(kind_sets)),
      by_identity_(true),
      action_dim_(action_dim),
      steps_(episode_steps) {
  CheckShape();
}

void GraphDataset::CheckShape() const {
  if (kind_sets_.empty() || kind_sets_.size() > 255)
    throw std::invalid_argument("GraphDataset: between 1 and 255 kind lists");
  for (const auto& kinds : kind_sets_) {
    if (layout_.num_entities < 1 || static_cast<int>(kinds.size()) != layout_.num_entities)
      throw std::invalid_argument("GraphDataset: entity kinds do not match the layout");
    for (uint16_t k : kinds)
      if (k >= layout_.num_kinds) throw std::invalid_argument("GraphDataset: entity kind outside the one-hot width");
    // a graph over the catalogue is indexed by kind: a kind twice in an episode is ambiguous
    if (by_identity_)
      for (uint16_t k : kinds)
        if (std::count(kinds.begin(), kinds.end(), k) > 1)
          throw std::invalid_argument("GraphDataset: a kind list of combinations repeats a kind");
  }
  if (action_dim_ < 1 || steps_ < 1)
    throw std::invalid_argument("GraphDataset: action_dim and episode_steps must be positive");
}

GraphDataset GraphDataset::ForShape(const DatasetShape& shape, int episode_steps) {
  if (shape.episode_kinds.empty())
    return GraphDataset(shape.layout, shape.entity_kinds, shape.action_dim, episode_steps);
  rl::EntityLayout layout = shape.layout;
  layout.num_entities = static_cast<int>(shape.episode_kinds.front().size());
  return GraphDataset(layout, shape.episode_kinds, shape.action_dim, episode_steps);
}

GraphDataset GraphDataset::EmptyCopy() const {
  GraphDataset empty = *this;
  empty.positions_.clear();
  empty.actions_.clear();
  empty.set_of_.clear();
  empty.train_.clear();
  empty.held_out_.clear();
  return empty;
}

std::vector<uint16_t> GraphDataset::graph_kinds() const {
  if (!combinations()) return entity_kinds();
  std::vector<uint16_t> kinds;
  for (int k = 0; k < layout_.num_kinds; ++k) kinds.push_back(static_cast<uint16_t>(k));
  return kinds;
}

GraphDataset GraphDataset::ShapedLike(const rl::Episode& episode) {
  return GraphDataset(episode.layout, episode.entity_kinds, episode.action_dim, episode.num_steps);
}

std::string GraphDataset::Convert(const rl::Episode& episode, StoredEpisode* out) const {
  if (!links::GraphServiceWants(episode.mode, training_episodes_))
    return training_episodes_ ? "neither an explore nor a training episode" : "not an explore episode";
  if (!(episode.layout == layout_)) return "entity layout differs from the data set's";
  const auto set = std::find(kind_sets_.begin(), kind_sets_.end(), episode.entity_kinds);
  if (set == kind_sets_.end())
    return combinations() ? "entity kinds are none of the training object sets"
                          : "entity kinds differ from the data set's";
  if (episode.action_dim != action_dim_) return "action size differs from the data set's";
  if (episode.num_steps != steps_)
    return "episode has " + std::to_string(episode.num_steps) + " steps, expected " + std::to_string(steps_);
  if (std::string problem = rl::ValidateEpisode(episode, rl::LimitsOfLayout(layout_, action_dim_)); !problem.empty())
    return problem;
  // keep xy only; the kind one-hot is rebuilt from entity_kinds
  const int n = layout_.num_entities;
  out->positions.assign(static_cast<size_t>(steps_ + 1) * n * 2, 0.f);
  for (int t = 0; t <= steps_; ++t) {
    const float* s = episode.state(t);
    for (int e = 0; e < n; ++e) {
      out->positions[(static_cast<size_t>(t) * n + e) * 2] = layout_.x(s, e);
      out->positions[(static_cast<size_t>(t) * n + e) * 2 + 1] = layout_.y(s, e);
    }
  }
  out->set = static_cast<uint8_t>(set - kind_sets_.begin());
  out->actions.assign(episode.actions.begin(), episode.actions.begin() + static_cast<size_t>(steps_) * action_dim_);
  return "";
}

std::string GraphDataset::Add(const rl::Episode& episode) {
  StoredEpisode stored;
  if (std::string problem = Convert(episode, &stored); !problem.empty()) return problem;
  positions_.push_back(std::move(stored.positions));
  set_of_.push_back(stored.set);
  actions_.push_back(std::move(stored.actions));
  if (training_episodes_) train_.push_back(size() - 1);
  return "";
}

std::string GraphDataset::Replace(int index, const rl::Episode& episode) {
  if (index < 0 || index >= size())
    throw std::out_of_range("GraphDataset::Replace: no episode " + std::to_string(index));
  StoredEpisode stored;
  if (std::string problem = Convert(episode, &stored); !problem.empty()) return problem;
  positions_[index] = std::move(stored.positions);
  set_of_[index] = stored.set;
  actions_[index] = std::move(stored.actions);
  return "";
}

GraphDataset GraphDataset::ForTrainingEpisodes(int episode_steps) const {
  GraphDataset out = EmptyCopy();
  out.steps_ = episode_steps;
  out.CheckShape();
  out.training_episodes_ = true;
  return out;
}

void GraphDataset::Save(nn::ByteWriter& out) const {
  out.Put<int32_t>(layout_.num_entities);
  out.Put<int32_t>(layout_.num_kinds);
  out.Put<uint8_t>(layout_.velocities ? 1 : 0);
  out.PutVector(FlatKinds(kind_sets_));
  out.Put<int32_t>(action_dim_);
  out.Put<int32_t>(steps_);
  out.Put<uint64_t>(positions_.size());
  for (size_t e = 0; e < positions_.size(); ++e) {
    out.PutVector(positions_[e]);
    out.PutVector(actions_[e]);
  }
  // which combination each episode is (one kind list: the format of before, nothing more)
  if (combinations()) out.PutVector(set_of_);
}

void GraphDataset::Load(nn::ByteReader& in) {
  if (size() != 0) throw std::logic_error("GraphDataset::Load: the data set is not empty");
  rl::EntityLayout layout;
  layout.num_entities = in.Get<int32_t>();
  layout.num_kinds = in.Get<int32_t>();
  layout.velocities = in.Get<uint8_t>() != 0;
  const std::vector<uint16_t> kinds = in.GetVector<uint16_t>();
  const int action_dim = in.Get<int32_t>();
  const int steps = in.Get<int32_t>();
  auto differs = [](const std::string& what) {
    return nn::CheckpointError("graph data set: " + what + " differs from this run's");
  };
  if (!(layout == layout_)) throw differs("entity layout");
  if (kinds != FlatKinds(kind_sets_)) throw differs("entity kinds");
  if (action_dim != action_dim_) throw differs("action size");
  if (steps != steps_) throw differs("episode length");
  const auto count = in.Get<uint64_t>();
  const size_t xy_size = static_cast<size_t>(steps_ + 1) * layout_.num_entities * 2;
  const size_t action_size = static_cast<size_t>(steps_) * action_dim_;
  // each episode needs at least its two counts: a huge count fails here, not in a reserve
  if (count > in.remaining() / 16)
    throw nn::CheckpointError("graph data set: episode count " + std::to_string(count) + " exceeds the bytes");
  std::vector<std::vector<float>> positions, actions;
  for (uint64_t e = 0; e < count; ++e) {
    positions.push_back(in.GetVector<float>());
    actions.push_back(in.GetVector<float>());
    if (positions.back().size() != xy_size || actions.back().size() != action_size)
      throw nn::CheckpointError("graph data set: episode " + std::to_string(e) + " has the wrong size");
    for (const auto* values : {&positions.back(), &actions.back()})
      for (float v : *values)
        if (!std::isfinite(v))
          throw nn::CheckpointError("graph data set: episode " + std::to_string(e) + " is not finite");
  }
  std::vector<uint8_t> set_of(count, 0);
  if (combinations()) {
    set_of = in.GetVector<uint8_t>();
    if (set_of.size() != count) throw nn::CheckpointError("graph data set: combinations of the wrong size");
    for (uint8_t s : set_of)
      if (s >= kind_sets_.size()) throw nn::CheckpointError("graph data set: an episode of an unknown combination");
  }
  positions_ = std::move(positions);
  actions_ = std::move(actions);
  set_of_ = std::move(set_of);
  if (training_episodes_) {
    train_.resize(positions_.size());
    std::iota(train_.begin(), train_.end(), 0);
  }
}

void GraphDataset::Split(double held_out_fraction, uint64_t seed) {
  std::vector<int> order(size());
  std::iota(order.begin(), order.end(), 0);
  nn::Rng rng(seed);
  // Fisher-Yates with our own draws so the split is the same on every platform
  for (int i = size() - 1; i > 0; --i) {
    const int j = static_cast<int>(rng() % static_cast<uint64_t>(i + 1));
    std::swap(order[i], order[j]);
  }
  const int held = static_cast<int>(std::lround(held_out_fraction * size()));
  if (held < 1 || held >= size())
    throw std::logic_error("GraphDataset::Split: " + std::to_string(size()) +
                           " episodes leave an empty training or held-out set");
  train_.assign(order.begin(), order.end() - held);
  held_out_.assign(order.end() - held, order.end());
  std::sort(train_.begin(), train_.end());
  std::sort(held_out_.begin(), held_out_.end());
}

template <typename T>
void GraphDataset::SampleWindows(int batch, int window, nn::Rng& rng, WindowBatch<T>* out) const {
  if (train_.empty()) throw std::logic_error("GraphDataset: Split before sampling");
  if (window < 1 || window > steps_) throw std::invalid_argument("window outside the episode");
  std::vector<int> episodes(batch), starts(batch);
  const uint64_t num_starts = static_cast<uint64_t>(steps_ - window + 1);
  for (int b = 0; b < batch; ++b) {
    episodes[b] = train_[rng() % train_.size()];
    starts[b] = static_cast<int>(rng() % num_starts);
  }
  Fill(episodes, starts, window, out);
}

template <typename T>
void GraphDataset::EpisodeBatch(const std::vector<int>& episodes, WindowBatch<T>* out) const {
  Fill(episodes, std::vector<int>(episodes.size(), 0), steps_, out);
}

template <typename T>
void GraphDataset::Fill(const std::vector<int>& episodes, const std::vector<int>& starts, int window,
                        WindowBatch<T>* out) const {
  const int batch = static_cast<int>(episodes.size());
  const int n = num_entities(), k = num_kinds(), a = action_dim_;
  out->batch = batch;
  out->num_entities = n;
  out->inputs.resize(window);
  out->deltas.resize(window);
  for (int t = 0; t < window; ++t) {
    nn::Matrix<T>& x = out->inputs[t];
    nn::Matrix<T>& d = out->deltas[t];
    x.setZero(static_cast<Eigen::Index>(batch) * n, input_dim());
    d.resize(static_cast<Eigen::Index>(batch) * n, 2);
    for (int b = 0; b < batch; ++b) {
      const int ep = episodes[b], step = starts[b] + t;
      const float* act = action(ep, step);
      const std::vector<uint16_t>& kinds = episode_kinds(ep);
      for (int e = 0; e < n; ++e) {
        const Eigen::Index row = static_cast<Eigen::Index>(b) * n + e;
        const float* now = position(ep, step, e);
        const float* next = position(ep, step + 1, e);
        x(row, 0) = now[0];
        x(row, 1) = now[1];
        x(row, 2 + kinds[e]) = T(1);
        for (int i = 0; i < a; ++i) x(row, 2 + k + i) = act[i];
        d(row, 0) = T(next[0]) - T(now[0]);
        d(row, 1) = T(next[1]) - T(now[1]);
      }
    }
  }
}

template void GraphDataset::SampleWindows<float>(int, int, nn::Rng&, WindowBatch<float>*) const;
template void GraphDataset::SampleWindows<double>(int, int, nn::Rng&, WindowBatch<double>*) const;
template void GraphDataset::EpisodeBatch<float>(const std::vector<int>&, WindowBatch<float>*) const;
template void GraphDataset::EpisodeBatch<double>(const std::vector<int>&, WindowBatch<double>*) const;

std::vector<double> ActionCorrelations(const GraphDataset& data) {
  const int n = data.graph_entities(), a = data.action_dim();
  std::vector<double> score(n, 0.0);
  // position of graph entity g in each episode (-1: absent)
  auto position = [&](int ep, int g) {
    for (int e = 0; e < data.num_entities(); ++e)
      if (data.graph_entity(ep, e) == g) return e;
    return -1;
  };
  for (int g = 0; g < n; ++g) {
    for (int i = 0; i < a; ++i) {
      double best = 0;
      for (int axis = 0; axis < 2; ++axis) {
        // one pass of sums for the Pearson correlation of action i and the axis change
        double su = 0, sv = 0, suu = 0, svv = 0, suv = 0, count = 0;
        for (int ep = 0; ep < data.size(); ++ep) {
          const int e = position(ep, g);
          if (e < 0) continue;
          for (int t = 0; t < data.episode_steps(); ++t) {
            const double u = data.action(ep, t)[i];
            const double v = data.position(ep, t + 1, e)[axis] - data.position(ep, t, e)[axis];
            su += u;
            sv += v;
            suu += u * u;
            svv += v * v;
            suv += u * v;
            count += 1;
          }
        }
        if (count < 2) continue;
        const double cov = suv / count - su / count * sv / count;
        const double var_u = suu / count - su / count * su / count;
        const double var_v = svv / count - sv / count * sv / count;
        // an entity that never moves has no correlation
        if (var_u <= 1e-18 || var_v <= 1e-18) continue;
        best = std::max(best, std::abs(cov) / std::sqrt(var_u * var_v));
      }
      score[g] += best / a;
    }
  }
  return score;
}

int SelectActionEntity(const GraphDataset& data) {
  const std::vector<double> score = ActionCorrelations(data);
  return static_cast<int>(std::max_element(score.begin(), score.end()) - score.begin());
}

}  // namespace srics::graph_service
