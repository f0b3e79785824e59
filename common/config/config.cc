#include "common/config/config.h"

#include <memory>
#include <string>

#include "common/config/sections.h"

namespace srics::config {
namespace {

Config ParseTree(const YAML::Node& root, std::shared_ptr<const OriginMap> origins, const std::string& name) {
  Config config;
  config.source_file = name;
  YamlSection top(root, "", origins, name);
  ParseRun(top.Child("run"), &config.run);
  ParseTransport(top.Child("transport"), &config.transport);
  ParseEnv(top.Child("env"), &config.env);
  ParseGraph(top.Child("graph"), &config.graph);
  ParseAgent(top.Child("agent"), &config.agent);
  ParseLearner(top.Child("learner"), &config.learner);
  ParseActors(top.Child("actors"), &config.actors);
  // rules across sections
  if (config.graph.refine_after_publish && config.actors.train_episode_steps < config.graph.window)
    top.Child("graph").FailRule(
        "window", "must not exceed actors.train_episode_steps (" + std::to_string(config.actors.train_episode_steps) +
                      ") with refine_after_publish: refinement trains on windows of training episodes");
  // HAC's levels play whole episodes from a reset (actor_loop.cc): a chain would be ignored
  if (config.run.method == Method::kHac && config.actors.train_chain_episodes > 1)
    top.Child("actors").FailRule("train_chain_episodes",
                                 "must be 1 with run.method hac: HAC's training episodes always start from a reset");
  top.Finish();
  YAML::Emitter emitter;
  emitter << root;
  config.effective_yaml = emitter.c_str();
  YAML::Emitter resolved;
  resolved << top.resolved();
  config.resolved_yaml = resolved.c_str();
  return config;
}

}  // namespace

const char* MethodName(Method method) {
  switch (method) {
    case Method::kSrics: return "srics";
    case Method::kSricsNoSelectivity: return "srics_no_selectivity";
    case Method::kSricsNoSelectivityNoOrder: return "srics_no_selectivity_no_order";
    case Method::kSmorl: return "smorl";
    case Method::kSacHer: return "sac_her";
    case Method::kHac: return "hac";
  }
  return "unknown";
}

Config LoadConfig(const std::string& file, const std::vector<std::string>& overrides) {
  try {
    auto origins = std::make_shared<OriginMap>();
    YAML::Node root = LoadMergedYaml(file, origins.get());
    for (const auto& assignment : overrides) ApplyOverride(&root, assignment, origins.get());
    return ParseTree(root, origins, file);
  } catch (const YAML::Exception& e) {
    // every check names file and key itself; this is the net under yaml-cpp's own errors
    throw ConfigError(file + (e.mark.is_null() ? "" : ":" + std::to_string(e.mark.line + 1)) + ": " + e.msg);
  }
}

std::string RecordedRunId(const std::string& config_yaml) {
  try {
    const YAML::Node root = LoadPlainYamlFile(config_yaml);
    const YAML::Node id = root.IsMap() && root["transport"].IsMap() ? root["transport"]["run_id"] : YAML::Node();
    if (!id.IsScalar() || id.Scalar().empty() || id.Scalar() == kAutoRunId) return "";
    return id.Scalar();
  } catch (const YAML::Exception&) {
    return "";
  } catch (const ConfigError&) {  // absent, over the size limit, anchors: no run id recorded
    return "";
  }
}

namespace {

YAML::Node ParseRoot(const std::string& yaml_text, const std::string& name) {
  YAML::Node root = ParsePlainYaml(yaml_text, name);
  if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) throw ConfigError(name + ": expected a mapping at the top level");
  CheckKeys(root, "", name, true);
  return root;
}

Config ParseRootWith(YAML::Node root, const std::vector<std::string>& overrides, const std::string& name) {
  try {
    auto origins = std::make_shared<OriginMap>();
    for (const auto& assignment : overrides) ApplyOverride(&root, assignment, origins.get());
    return ParseTree(root, origins, name);
  } catch (const YAML::Exception& e) {
    throw ConfigError(name + (e.mark.is_null() ? "" : ":" + std::to_string(e.mark.line + 1)) + ": " + e.msg);
  }
}

}  // namespace

Config ParseConfig(const std::string& yaml_text, const std::string& name) {
  return ParseRootWith(ParseRoot(yaml_text, name), {}, name);
}

const std::vector<EarlierDefault>& EarlierDefaults() {
  // issue 35, 2026-12-07: the tie-evidence KL and the lowest-loss publish became the defaults
  // (docs/results.md)
  static const std::vector<EarlierDefault> earlier = {
      {"graph.tie_evidence_per_episode", "0"},
      {"graph.tie_kl_factor", "1"},
      {"graph.publish", "last"},
      // issue 35, 2026-12-07 (evening): object pairs read against the tie evidence (docs/results.md)
      {"graph.tied_pair_threshold", "0"},
      {"graph.untied_pair_threshold", "0"},
  };
  return earlier;
}

namespace {

// EarlierDefaultsOf on a parsed record (the record is parsed once per use)
std::vector<std::string> EarlierDefaultsOfRoot(const YAML::Node& root) {
  std::vector<std::string> overrides;
  for (const EarlierDefault& d : EarlierDefaults()) {
    const std::string key = d.key;
    const size_t dot = key.find('.');
    const YAML::Node section = root[key.substr(0, dot)];
    // (a missing key reads as an invalid node, on which only the bool test is allowed)
    if (!section || !section.IsMap() || !section[key.substr(dot + 1)]) overrides.push_back(key + "=" + d.value);
  }
  return overrides;
}

}  // namespace

std::vector<std::string> EarlierDefaultsOf(const std::string& recorded_yaml, const std::string& name) {
  return EarlierDefaultsOfRoot(ParseRoot(recorded_yaml, name));
}

Config ParseRecordedConfig(const std::string& yaml_text, const std::string& name) {
  YAML::Node root = ParseRoot(yaml_text, name);
  const std::vector<std::string> earlier = EarlierDefaultsOfRoot(root);
  return ParseRootWith(root, earlier, name);
}

}  // namespace srics::config
