#include "deploy/launcher/supervisor.h"

#include <signal.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <thread>

namespace srics::launcher {
namespace {

std::string SecondsText(std::chrono::milliseconds d) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.1fs", static_cast<double>(d.count()) / 1000.0);
  return buffer;
}

}  // namespace

const char* ChildPhaseName(ChildPhase phase) {
  switch (phase) {
    case ChildPhase::kNotStarted: return "not started";
    case ChildPhase::kRunning: return "running";
    case ChildPhase::kWaitingToRestart: return "restarting";
    case ChildPhase::kFinished: return "finished";
    case ChildPhase::kFailed: return "failed";
  }
  return "invalid";
}

Supervisor::Supervisor(SupervisorOptions options) : options_(std::move(options)) {}

Supervisor::~Supervisor() {
  options_.on_event = nullptr;  // its captures may already be gone
  StopAll();
}

void Supervisor::Event(const std::string& text) const {
  if (options_.on_event) options_.on_event(text);
}

size_t Supervisor::Add(ChildSpec spec) {
  if (spec.argv.empty()) throw std::invalid_argument("child '" + spec.name + "' has no program");
  if (Find(spec.name)) throw std::invalid_argument("duplicate child name '" + spec.name + "'");
  Child child;
  child.status.name = spec.name;
  child.spec = std::move(spec);
  children_.push_back(std::move(child));
  return children_.size() - 1;
}

std::optional<size_t> Supervisor::Find(const std::string& name) const {
  for (size_t i = 0; i < children_.size(); ++i)
    if (children_[i].spec.name == name) return i;
  return std::nullopt;
}

bool Supervisor::Launch(Child* child, std::string* error) {
  SpawnOptions spawn = options_.spawn;
  spawn.output_file = child->spec.output_file;
  try {
    child->process = ChildProcess::Spawn(child->spec.argv, spawn);
  } catch (const std::exception& e) {
    *error = e.what();
    return false;
  }
  child->status.phase = ChildPhase::kRunning;
  child->status.pid = child->process.pid();
  child->status.started_at = SteadyClock::now();
  return true;
}

void Supervisor::StartAll() {
  for (Child& child : children_) {
    if (child.status.phase != ChildPhase::kNotStarted) continue;
    std::string error;
    if (!Launch(&child, &error)) {
      child.status.phase = ChildPhase::kFailed;
      StopAll();
      throw std::runtime_error("cannot start " + child.spec.name + ": " + error);
    }
    Event(child.spec.name + " started (pid " + std::to_string(child.status.pid) + ")");
  }
}

std::chrono::milliseconds Supervisor::BackoffDelay(const BackoffPolicy& policy, uint32_t consecutive_failures) {
  const double exponent = consecutive_failures > 0 ? consecutive_failures - 1.0 : 0.0;
  const double ms = static_cast<double>(policy.initial.count()) * std::pow(policy.factor, std::min(exponent, 60.0));
  return std::chrono::milliseconds(static_cast<int64_t>(std::min(ms, static_cast<double>(policy.max.count()))));
}

bool Supervisor::Kill(size_t index, const std::string& why) {
  Child& child = children_.at(index);
  if (child.status.phase != ChildPhase::kRunning) return false;
  Event(child.spec.name + " " + why + "; killing it (SIGKILL) so that it restarts");
  return child.process.Signal(SIGKILL);
}

std::vector<size_t> Supervisor::Tick() {
  std::vector<size_t> ended;
  const auto now = SteadyClock::now();
  for (size_t i = 0; i < children_.size(); ++i) {
    Child& child = children_[i];
    ChildStatus& s = child.status;
    if (s.phase == ChildPhase::kRunning) {
      const std::optional<ExitStatus> exit = child.process.Poll();
      if (!exit) continue;
      s.last_exit = exit;
      s.pid = 0;
      const std::string what = child.spec.name + " ended: " + exit->Describe();
      if (exit->success()) {
        s.phase = ChildPhase::kFinished;
        Event(what);
        ended.push_back(i);
        continue;
      }
      if (now - s.started_at >= options_.backoff.reset_after) s.consecutive_failures = 0;
      ++s.consecutive_failures;
      const auto& finals = child.spec.final_exit_codes;
      const bool final_code = !exit->signaled && std::find(finals.begin(), finals.end(), exit->code) != finals.end();
      const bool allowed = child.spec.restart == RestartPolicy::kOnFailure && !final_code &&
                           (child.spec.max_restarts < 0 || s.restarts < static_cast<uint32_t>(child.spec.max_restarts));
      if (!allowed) {
        s.phase = ChildPhase::kFailed;
        Event(what + (child.spec.restart == RestartPolicy::kNever ? std::string("; not restarted")
                      : final_code ? std::string("; not restarted (a restart cannot help: see its log)")
                                   : "; gave up after " + std::to_string(s.restarts) + " restarts"));
        ended.push_back(i);
        continue;
      }
      const auto delay = BackoffDelay(options_.backoff, s.consecutive_failures);
      s.phase = ChildPhase::kWaitingToRestart;
      s.restart_at = now + delay;
      Event(what + "; restart " + std::to_string(s.restarts + 1) + " in " + SecondsText(delay));
    }
    if (s.phase == ChildPhase::kWaitingToRestart && now >= s.restart_at) {
      ++s.restarts;
      std::string error;
      if (Launch(&child, &error)) {
        Event(child.spec.name + " restarted (pid " + std::to_string(s.pid) + ", restart " + std::to_string(s.restarts) +
              ")");
      } else {
        // counts as another failure: back off further (or give up at the limit)
        ++s.consecutive_failures;
        const bool allowed = child.spec.max_restarts < 0 || s.restarts < static_cast<uint32_t>(child.spec.max_restarts);
        if (allowed) {
          const auto delay = BackoffDelay(options_.backoff, s.consecutive_failures);
          s.restart_at = now + delay;
          Event(child.spec.name + " could not be restarted (" + error + "); next try in " + SecondsText(delay));
        } else {
          s.phase = ChildPhase::kFailed;
          Event(child.spec.name + " could not be restarted (" + error + "); giving up");
          ended.push_back(i);
        }
      }
    }
  }
  return ended;
}

bool Supervisor::StopSome(const std::vector<size_t>& indices) {
  std::vector<size_t> signaled;
  for (size_t i : indices) {
    Child& child = children_[i];
    if (child.status.phase == ChildPhase::kWaitingToRestart || child.status.phase == ChildPhase::kNotStarted) {
      child.status.phase = ChildPhase::kFinished;  // pending restart cancelled
      continue;
    }
    if (child.status.phase != ChildPhase::kRunning) continue;
    child.process.Signal(options_.stop_signal);
    signaled.push_back(i);
  }
  const auto deadline = SteadyClock::now() + options_.stop_timeout;
  bool clean = true;
  for (;;) {
    bool any_running = false;
    for (size_t i : signaled) any_running |= !children_[i].process.Poll().has_value();
    if (!any_running || SteadyClock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  for (size_t i : signaled) {
    Child& child = children_[i];
    ChildStatus& s = child.status;
    if (!child.process.Poll()) {
      Event(child.spec.name + " did not stop within " + SecondsText(options_.stop_timeout) + ": SIGKILL");
      child.process.Kill();
      clean = false;
      s.phase = ChildPhase::kFailed;
    } else {
      s.phase = ChildPhase::kFinished;
    }
    s.last_exit = child.process.exit_status();
    s.pid = 0;
    Event(child.spec.name + " stopped: " + s.last_exit->Describe());
  }
  return clean;
}

bool Supervisor::StopAll() {
  std::vector<size_t> all(children_.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  return StopSome(all);
}

bool Supervisor::Stop(size_t index) { return StopSome({index}); }

uint32_t Supervisor::total_restarts() const {
  uint32_t total = 0;
  for (const Child& child : children_) total += child.status.restarts;
  return total;
}

bool Supervisor::AllDown() const {
  return std::none_of(children_.begin(), children_.end(), [](const Child& c) {
    return c.status.phase == ChildPhase::kRunning || c.status.phase == ChildPhase::kWaitingToRestart;
  });
}

}  // namespace srics::launcher
