#pragma once
// The whole configuration of a run, parsed once from YAML into plain structs.
//
//   Config config = LoadConfig("deploy/configs/rearrange-3.yaml", {"actors.count=4"});
//
// Unknown keys, wrong types and out-of-range values throw ConfigError naming the file (and
// line), the key path and what was expected. Files may start with `extends: base.yaml`.

#include <string>
#include <vector>

#include "common/config/actor_config.h"
#include "common/config/agent_config.h"
#include "common/config/config_error.h"
#include "common/config/env_config.h"
#include "common/config/graph_config.h"
#include "common/config/learner_config.h"
#include "common/config/run_config.h"
#include "common/config/transport_config.h"

namespace srics::config {

struct Config {
  RunConfig run;
  TransportConfig transport;
  EnvConfig env;
  GraphConfig graph;
  AgentConfig agent;
  LearnerConfig learner;
  ActorConfig actors;
  std::string source_file;     // the file it was loaded from
  std::string effective_yaml;  // the merged YAML (extends + overrides), for the run folder
  // every key read with the value it resolved to, the defaults of this binary filled in: what a
  // resumed run is compared with (a default that changed between binaries is a changed config).
  // A record, not a config to load (rules across keys are not re-checked on it).
  std::string resolved_yaml;
};

// Loads `file`, applies each "key.path=value" override, validates everything.
Config LoadConfig(const std::string& file, const std::vector<std::string>& overrides = {});

// The transport.run_id recorded in an effective configuration (a run folder's config.yaml),
// or "" when the file does not exist, is not YAML or has no run id other than "auto". Throws
// nothing: it only tells whether an earlier launch chose a run id.
std::string RecordedRunId(const std::string& config_yaml);

// Parses YAML text (for tests and for configs received from elsewhere); `name` is used in
// error messages in place of a file name.
Config ParseConfig(const std::string& yaml_text, const std::string& name);

// A setting whose default changed after run folders had recorded it only when given: a record
// (resolved-config.yaml) without the key is from a run that had `value`. Since the change the
// key is always recorded.
struct EarlierDefault {
  const char* key;    // "section.key"
  const char* value;  // as an override's value
};
const std::vector<EarlierDefault>& EarlierDefaults();

// The overrides ("graph.tie_kl_factor=1") that give a run recorded in `recorded_yaml` (a
// resolved-config.yaml's text) the earlier defaults it ran with: one per EarlierDefaults key the
// record lacks. Throws ConfigError for a record that is not YAML (`name` in the message).
std::vector<std::string> EarlierDefaultsOf(const std::string& recorded_yaml, const std::string& name);

// Parses a recorded resolved-config.yaml as this binary resolves it, the earlier defaults the
// record's run had (EarlierDefaultsOf) applied: a default changed since is a change.
Config ParseRecordedConfig(const std::string& yaml_text, const std::string& name);

}  // namespace srics::config
