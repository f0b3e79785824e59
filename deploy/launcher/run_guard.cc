#include "deploy/launcher/run_guard.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <sstream>
#include <tuple>

#include "common/transport/endpoint.h"

namespace srics::launcher {

namespace tr = srics::transport;

namespace {

constexpr const char* kPrefix = "incarnation since ";
constexpr size_t kMaxActorsText = 150;  // longer: "actors:*" (any actor), the detail holds 256
constexpr int kAnyActor = -1;           // "actors:*" read back

// "0-3,5,7-9"
std::string Ranges(std::vector<int> ids) {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::string text;
  for (size_t i = 0; i < ids.size();) {
    size_t j = i;
    while (j + 1 < ids.size() && ids[j + 1] == ids[j] + 1) ++j;
    if (!text.empty()) text += ',';
    text += std::to_string(ids[i]);
    if (j > i) text += '-' + std::to_string(ids[j]);
    i = j + 1;
  }
  return text;
}

// The ids of "0-3,5"; nothing when it is not such a list (or "*").
std::optional<std::vector<int>> ParseRanges(const std::string& text) {
  std::vector<int> ids;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    int first = 0, last = 0;
    char tail = 0;
    if (std::sscanf(item.c_str(), "%d-%d%c", &first, &last, &tail) == 2) {
    } else if (std::sscanf(item.c_str(), "%d%c", &first, &tail) == 1) {
      last = first;
    } else {
      return std::nullopt;
    }
    if (first < 0 || last < first || last - first > 100000) return std::nullopt;
    for (int k = first; k <= last; ++k) ids.push_back(k);
  }
  return ids;
}

// "launcher on host h1, pid 4242", "actor 3 on host h1, pid 4242"
std::string Who(const rl::NodeStatus& status) {
  std::string who = status.role;
  if (status.role == "actor") who += " " + std::to_string(status.node_id);
  return who + " on host " + status.host + ", pid " + std::to_string(status.pid);
}

}  // namespace

Incarnation ThisIncarnation(const RoleShare& share) {
  char host[tr::kHostMaxLength] = {};
  gethostname(host, sizeof host - 1);
  return {.host = host,
          .pid = static_cast<int32_t>(getpid()),
          .start_ms =
              std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
                  .count(),
          .share = share};
}

std::string IncarnationDetail(const Incarnation& incarnation) {
  std::string text = kPrefix + std::to_string(incarnation.start_ms) + "; roles";
  const RoleShare& share = incarnation.share;
  if (share.graph) text += " graph";
  if (share.learner) text += " learner";
  if (!share.actor_ids.empty()) {
    std::string ids = Ranges(share.actor_ids);
    text += " actors:" + (ids.size() > kMaxActorsText ? std::string("*") : ids);
  }
  return text;
}

std::optional<Incarnation> IncarnationOf(const rl::NodeStatus& status) {
  const std::string& detail = status.report.detail;
  if (detail.rfind(kPrefix, 0) != 0) return std::nullopt;
  std::stringstream in(detail.substr(std::string(kPrefix).size()));
  Incarnation incarnation{.host = status.host, .pid = status.pid};
  std::string word;
  if (!(in >> word) || word.empty() || word.back() != ';') return std::nullopt;
  word.pop_back();
  try {
    size_t used = 0;
    incarnation.start_ms = std::stoll(word, &used);
    if (used != word.size()) return std::nullopt;
  } catch (const std::exception&) {
    return std::nullopt;
  }
  if (!(in >> word) || word != "roles") return std::nullopt;
  RoleShare& share = incarnation.share;
  share = {.graph = false, .learner = false, .whole_run = false};
  // the roles, up to the end or the rejection summary StatusPublisher appends (" | rejected: ...")
  while (in >> word && word != "|") {
    if (word == "graph") {
      share.graph = true;
    } else if (word == "learner") {
      share.learner = true;
    } else if (word == "actors:*") {
      share.actor_ids = {kAnyActor};
    } else if (word.rfind("actors:", 0) == 0) {
      const auto ids = ParseRanges(word.substr(7));
      if (!ids) return std::nullopt;
      share.actor_ids = *ids;
    } else {
      return std::nullopt;
    }
  }
  return incarnation;
}

bool SharesOverlap(const RoleShare& a, const RoleShare& b) {
  if ((a.graph && b.graph) || (a.learner && b.learner)) return true;
  const auto any = [](const RoleShare& s) {
    return std::find(s.actor_ids.begin(), s.actor_ids.end(), kAnyActor) != s.actor_ids.end();
  };
  if ((any(a) && !b.actor_ids.empty()) || (any(b) && !a.actor_ids.empty())) return true;
  for (int k : a.actor_ids)
    if (std::find(b.actor_ids.begin(), b.actor_ids.end(), k) != b.actor_ids.end()) return true;
  return false;
}

Judgement Judge(const Incarnation& self, const rl::NodeStatus& status, bool roles_started) {
  const bool own_process = status.host == self.host && status.pid == self.pid;
  if (status.role == "launcher") {
    if (own_process) return {};
    Incarnation other;
    if (const auto parsed = IncarnationOf(status)) {
      other = *parsed;
    } else {
      // says no roles or start: taken as the whole run, there from the start
      other = {.host = status.host,
               .pid = status.pid,
               .start_ms = 0,
               .share = {.graph = true, .learner = true, .actor_ids = {kAnyActor}, .whole_run = true}};
    }
    if (!SharesOverlap(self.share, other.share)) return {};
    const bool first = std::tie(other.start_ms, other.host, other.pid) < std::tie(self.start_ms, self.host, self.pid);
    return {first ? Verdict::kWasFirst : Verdict::kCameLater, Who(status)};
  }
  if (roles_started || own_process) return {};
  const RoleShare& share = self.share;
  const bool mine = (status.role == "graph" && share.graph) || (status.role == "learner" && share.learner) ||
                    (status.role == "actor" && std::find(share.actor_ids.begin(), share.actor_ids.end(),
                                                         static_cast<int>(status.node_id)) != share.actor_ids.end());
  if (!mine) return {};
  return {Verdict::kWasFirst, Who(status)};
}

std::string SecondRunMessage(const std::string& run_id, int domain_id, const Judgement& other) {
  return "run id '" + run_id + "' is taken on DDS domain " + std::to_string(domain_id) + ": a run of it is live, its " +
         other.who +
         ". Two runs with one run id merge (each learner takes the other's episodes, the actors both learners' "
         "weights), so this one does not start. Pick another run id (--set transport.run_id=NEW_ID, or "
         "transport.run_id: auto for one per launch), or stop that run first: a run resumed in its folder "
         "(--run-dir) goes on once its launcher has exited.";
}

std::chrono::milliseconds ListenWindow(const config::TransportConfig& transport) {
  const double seconds = std::clamp(2.5 * transport.status_period_s, 2.0, 10.0);
  return std::chrono::milliseconds(static_cast<int64_t>(seconds * 1000));
}

RunGuard::RunGuard(const tr::Participant& participant, const RoleShare& share)
    : participant_(participant),
      self_(ThisIncarnation(share)),
      status_(participant, "launcher", static_cast<uint32_t>(self_.pid)) {}

rl::NodeReport RunGuard::Report(rl::NodePhase phase) const {
  rl::NodeReport report;
  report.phase = phase;
  report.detail = IncarnationDetail(self_);
  return report;
}

void RunGuard::Publish(rl::NodePhase phase) { status_.Publish(Report(phase)); }

std::string RunGuard::CheckAlone(std::chrono::milliseconds window) {
  // the reader first: this launcher's own status is heard (and is not in the way)
  tr::Reader<rl::NodeStatus> statuses(participant_);
  Publish(rl::NodePhase::kStarting);
  using Clock = std::chrono::steady_clock;
  const auto period = std::chrono::milliseconds(static_cast<int64_t>(participant_.config().status_period_s * 1000));
  const auto end = Clock::now() + window;
  auto next_status = Clock::now() + period;
  rl::NodeStatus status;
  for (auto now = Clock::now(); now < end; now = Clock::now()) {
    if (now >= next_status) {
      Publish(rl::NodePhase::kStarting);
      next_status = now + period;
    }
    const auto wait =
        std::min(std::chrono::duration_cast<std::chrono::milliseconds>(end - now), std::chrono::milliseconds(100));
    const tr::TakeStatus taken = statuses.Take(&status, wait);
    if (taken == tr::TakeStatus::kShutdown) return "";
    if (taken != tr::TakeStatus::kSample) continue;
    const Judgement judgement = Judge(self_, status, /*roles_started=*/false);
    if (judgement.verdict == Verdict::kWasFirst) {
      // so that the first launcher's log names this one: its reader may not have matched this
      // writer when the statuses above went out (seen under load: the first never heard of it).
      // Two readers: this launcher's own and the first's monitor.
      status_.PublishBeforeLeaving(Report(rl::NodePhase::kStarting), 2, std::chrono::milliseconds(3000));
      return SecondRunMessage(participant_.run_id(), participant_.config().domain_id, judgement);
    }
  }
  return "";
}

}  // namespace srics::launcher
