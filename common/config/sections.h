#pragma once
// Internal: one parse function per section, each in its *_config.cc. Each reads every key of
// its mapping, checks ranges and cross-field rules, and calls Finish().

#include "common/config/config.h"
#include "common/config/yaml_section.h"

namespace srics::config {

void ParseRun(YamlSection section, RunConfig* out);
void ParseTransport(YamlSection section, TransportConfig* out);
void ParseEnv(YamlSection section, EnvConfig* out);
void ParseGraph(YamlSection section, GraphConfig* out);
void ParseAgent(YamlSection section, AgentConfig* out);
void ParseLearner(YamlSection section, LearnerConfig* out);
void ParseActors(YamlSection section, ActorConfig* out);

}  // namespace srics::config
