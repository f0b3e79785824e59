#include "common/transport/cyclone_xml.h"

#include <filesystem>
#include <sstream>
#include <stdexcept>

#include "common/transport/participant.h"

namespace srics::transport {
namespace internal {

std::string ExpandVariables(const std::string& text, const std::map<std::string, std::string>& values) {
  std::string out;
  size_t pos = 0;
  while (true) {
    const size_t start = text.find("${", pos);
    const size_t end = start == std::string::npos ? start : text.find('}', start);
    if (end == std::string::npos) break;
    const std::string inner = text.substr(start + 2, end - start - 2);
    const std::string name = inner.substr(0, inner.find(":-"));
    out.append(text, pos, start - pos);
    auto it = values.find(name);
    if (it != values.end())
      out += it->second;
    else
      out.append(text, start, end + 1 - start);
    pos = end + 1;
  }
  out.append(text, pos, std::string::npos);
  return out;
}

}  // namespace internal

namespace {

// Replaces the template's one <Peer .../> element by one element per comma-separated address.
std::string ExpandPeers(const std::string& xml, const std::string& peers) {
  const size_t start = xml.find("<Peer address=\"${SRICS_DDS_PEER");
  if (start == std::string::npos) throw std::logic_error("unicast.xml has no <Peer> template line");
  const size_t end = xml.find("/>", start) + 2;
  std::string elements;
  std::stringstream list(peers);
  for (std::string peer; std::getline(list, peer, ',');) {
    peer.erase(0, peer.find_first_not_of(" \t"));
    peer.erase(peer.find_last_not_of(" \t") + 1);
    if (peer.empty()) continue;
    if (peer.find_first_of("\"<>&") != std::string::npos)
      throw std::invalid_argument("transport.peers: '" + peer + "' is not an address");
    if (!elements.empty()) elements += "\n        ";
    elements += "<Peer address=\"" + peer + "\"/>";
  }
  if (elements.empty()) throw std::invalid_argument("transport.peers: no address for profile unicast");
  return xml.substr(0, start) + elements + xml.substr(end);
}

}  // namespace

std::string CycloneConfigFor(const config::TransportConfig& config) {
  using config::CycloneProfile;
  if (config.profile == CycloneProfile::kEnvironment) return "";
  if (config.profile == CycloneProfile::kFile) {
    const std::filesystem::path path = std::filesystem::absolute(config.cyclone_xml);
    if (!std::filesystem::exists(path))
      throw std::invalid_argument("transport.cyclone_xml: no such file '" + path.string() + "'");
    return "file://" + path.string();
  }
  // RTPS unicast ports: 7400 + 250 * domain + 10 + 2 * participant index (+1 for data)
  const int64_t top_port = 7400 + 250 * int64_t{config.domain_id} + 11 + 2 * int64_t{config.max_participants_per_host};
  if (top_port > 65535)
    throw std::invalid_argument("transport: domain_id " + std::to_string(config.domain_id) + " with " +
                                std::to_string(config.max_participants_per_host) +
                                " participants per host needs UDP port " + std::to_string(top_port) +
                                " (> 65535): lower domain_id or max_participants_per_host");
  if (config.network_interface.find_first_of("\"<>&") != std::string::npos)
    throw std::invalid_argument("transport.network_interface: '" + config.network_interface +
                                "' is not an interface name");
  std::map<std::string, std::string> values = {
      {"SRICS_DDS_MAX_PARTICIPANTS", std::to_string(config.max_participants_per_host)},
      {"SRICS_DDS_INTERFACE", config.network_interface},
      {"SRICS_DDS_AUTODETERMINE", config.network_interface.empty() ? "true" : "false"},
  };
  std::string xml = internal::CycloneTemplate(config.profile);
  if (config.profile == CycloneProfile::kUnicast) xml = ExpandPeers(xml, config.peers);
  return internal::ExpandVariables(xml, values);
}

}  // namespace srics::transport
