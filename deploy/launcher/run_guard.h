#pragma once
// One run id, one run (issue 39). Two `srics run` with one run id on one domain used to merge
// without a word: each learner took the other's episodes, the actors both learners' weights.
//
// Every launcher announces itself on the run's NodeStatus (role "launcher", node id its pid)
// with its incarnation: host and pid in the status, its start time and its roles in the detail
// ("incarnation since 1733400000123; roles graph learner actors:0-3"). Before it starts a role
// or writes a file, a launcher publishes its status and listens to the run's statuses for a
// few status periods (ListenWindow). NodeStatus is transient-local: a live process's last
// status arrives as soon as discovery matches, and a dead process's died with it. The launcher
// must leave (exit 2, RunGuard::CheckAlone's message) when it hears
//   - another launcher of the run whose roles overlap its own and that started first (start
//     time, then host, then pid: both compare the same numbers, so exactly one leaves), or
//   - a live learner, graph service or actor of its own share: none is its own yet.
// Roles restarted by their own launcher and a run resumed in its folder after its launcher
// ended hear no live process of the run, so they are no second run. Launchers of a run on
// several hosts (--roles) run different roles and do not overlap.
// While it runs, the launcher refuses a later launcher's statuses (they are not this run's:
// never in nodes.csv or the display, logged once) and leaves if it hears one that came first
// (a network that joined late).

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>

#include "common/config/transport_config.h"
#include "common/rl/updates.h"
#include "common/transport/participant.h"
#include "common/transport/status_publisher.h"
#include "common/transport/wire.h"
#include "deploy/launcher/launcher.h"

namespace srics::launcher {

// Who a launcher is.
struct Incarnation {
  std::string host;
  int32_t pid = 0;
  int64_t start_ms = 0;  // wall clock, ms since the epoch
  RoleShare share;
};

// This process, started now, running `share`.
Incarnation ThisIncarnation(const RoleShare& share);

// The detail of a launcher's NodeStatus: "incarnation since MS; roles graph learner actors:0-3,5".
std::string IncarnationDetail(const Incarnation& incarnation);
// A launcher's incarnation from its status (host and pid from the status' fields); nothing when
// the detail does not say it (then it is taken as the whole run, started at the epoch).
std::optional<Incarnation> IncarnationOf(const rl::NodeStatus& status);

// Whether two launchers run a role in common (the graph service, the learner or an actor id;
// actor id -1, "actors:*" read back, is any actor).
bool SharesOverlap(const RoleShare& a, const RoleShare& b);

enum class Verdict {
  kNotInTheWay,  // this launcher's own status, another role or a launcher of other roles
  kCameLater,    // a launcher of the same roles that started after this one: it leaves
  kWasFirst,     // a live process of this launcher's roles that is not its own: this one leaves
};
struct Judgement {
  Verdict verdict = Verdict::kNotInTheWay;
  std::string who;  // "launcher on host h1, pid 4242"
};
// What `status` (of this launcher's run) means for `self`. Before its roles started, any live
// learner, graph service or actor of its share was there first; after, they are its own.
Judgement Judge(const Incarnation& self, const rl::NodeStatus& status, bool roles_started);

// The user's message when `other` was there first: the run id, the other process (host, pid)
// and how to pick another run id.
std::string SecondRunMessage(const std::string& run_id, int domain_id, const Judgement& other);

// How long a starting launcher listens: 2.5 status periods, between 2 and 10 seconds.
std::chrono::milliseconds ListenWindow(const config::TransportConfig& transport);

// The launcher's own NodeStatus and the check before it starts anything.
class RunGuard {
 public:
  // The participant's run id is the run's. Throws transport::DdsError.
  RunGuard(const transport::Participant& participant, const RoleShare& share);

  // Publishes this launcher's status and listens for `window`. Returns "" when no other run of
  // this run id is there; else SecondRunMessage (the caller exits with kExitUsage before it
  // starts or writes anything). Returns "" at once when shutdown is requested.
  std::string CheckAlone(std::chrono::milliseconds window);
  // Publishes the status (the launcher's loop: every status period).
  void Publish(rl::NodePhase phase);
  const Incarnation& self() const { return self_; }

 private:
  rl::NodeReport Report(rl::NodePhase phase) const;  // this launcher's status: phase and incarnation

  const transport::Participant& participant_;
  Incarnation self_;
  transport::StatusPublisher status_;
};

}  // namespace srics::launcher
