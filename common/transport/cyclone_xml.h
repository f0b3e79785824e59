#pragma once
// Internal: the Cyclone XML templates (deploy/cyclonedds/) and their expansion.

#include <map>
#include <string>

#include "common/config/transport_config.h"

namespace srics::transport::internal {

// The template text of a built-in profile (loopback, lan, unicast); "" for the others.
const char* CycloneTemplate(config::CycloneProfile profile);

// Replaces ${NAME} and ${NAME:-default} for every NAME in `values`; other variables are left
// for Cyclone to expand from the environment.
std::string ExpandVariables(const std::string& text, const std::map<std::string, std::string>& values);

}  // namespace srics::transport::internal
