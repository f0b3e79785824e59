// The dashboard in a real browser (Debian's chromium, headless; tests/install-test-deps.sh
// installs it) against a live `srics run --in-process --http 0`: the page loads, draws the
// learning curve (an SVG path through the evaluations' points), and a later load shows more
// env steps; a screenshot is taken. Then the same page from `srics-monitor --run-dir` on the
// stopped run's folder, `srics-monitor --json` on it, and a second run asking for the taken
// port exits 2 naming it before making a run folder. SKIPs when chromium is not installed.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <httplib.h>
#include <signal.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "deploy/launcher/child_process.h"
#include "tests/common/files/test_files.h"
#include "tests/deploy/dashboard/json_reader.h"
#include "tests/deploy/tiny_run.h"

namespace srics::dashboard {
namespace {

namespace fs = std::filesystem;
using files::testing::ReadFile;
using launcher::ChildProcess;
using ::testing::HasSubstr;
using Json = testing::Json;

// A short SRICS run (Rearrange 1, tiny graph phase and warm-up, an evaluation every 400 env
// steps), long enough for the page to be loaded twice while it trains.
const std::vector<std::string> kShortRun =
    srics::testing::TinyRunSettings({"run.total_env_steps=20000", "actors.count=2", "actors.eval_every_env_steps=400"});

std::string Chromium() {
  for (const char* path : {"/usr/bin/chromium", "/usr/bin/chromium-browser"})
    if (fs::exists(path)) return path;
  return "";
}

// Runs a command, returns its stdout (stderr dropped).
std::string Capture(const std::string& command) {
  std::string out;
  FILE* pipe = popen((command + " 2>/dev/null").c_str(), "r");
  if (!pipe) return out;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  pclose(pipe);
  return out;
}

class Browser {
 public:
  explicit Browser(fs::path profile) : profile_(std::move(profile)) {}
  // The page's DOM after its script ran (a few seconds of its own time: two polls).
  std::string DumpDom(const std::string& url) const { return Capture(Command() + " --dump-dom '" + url + "'"); }
  void Screenshot(const std::string& url, const fs::path& png) const {
    Capture(Command() + " --window-size=1280,1700 --screenshot=" + png.string() + " '" + url + "'");
  }

 private:
  std::string Command() const {
    return "timeout 90 " + Chromium() + " --headless --disable-gpu --no-sandbox --no-first-run --hide-scrollbars" +
           " --user-data-dir=" + profile_.string() + " --virtual-time-budget=5000";
  }
  fs::path profile_;
};

// The env-step counter of a dumped page ("12,345" -> 12345), -1 when absent.
int64_t EnvStepsShown(const std::string& dom) {
  std::smatch m;
  if (!std::regex_search(dom, m, std::regex("id=\"env-steps\"[^>]*>([0-9,]+)<"))) return -1;
  std::string digits;
  for (char c : m[1].str())
    if (c != ',') digits += c;
  return std::stoll(digits);
}

// The number of points of the learning curve's object-distance path, 0 when there is none.
int CurvePoints(const std::string& dom) {
  std::smatch m;
  if (!std::regex_search(
          dom, m, std::regex("<path class=\"series curve-object\" d=\"(M[^\"]+)\"[^>]*data-points=\"([0-9]+)\"")))
    return 0;
  const std::string d = m[1].str();
  const int segments = static_cast<int>(std::count(d.begin(), d.end(), 'L'));
  EXPECT_EQ(segments + 1, std::stoi(m[2].str())) << d;
  return segments + 1;
}

// /api/state of a server, parsed; null document on failure.
std::optional<Json> State(int port) {
  httplib::Client client("127.0.0.1", port);
  client.set_read_timeout(std::chrono::seconds(5));
  auto response = client.Get("/api/state");
  if (!response || response->status != 200) return std::nullopt;
  return Json::Parse(response->body);
}

// Waits until `ready` holds for the server's document (or the deadline).
bool WaitFor(int port, std::chrono::seconds deadline, const std::function<bool(const Json&)>& ready) {
  const auto end = std::chrono::steady_clock::now() + deadline;
  while (std::chrono::steady_clock::now() < end) {
    if (auto doc = State(port); doc && doc->size() > 0 && ready(*doc)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  return false;
}

// The port a program printed ("... dashboard on http://127.0.0.1:PORT/"), 0 until it did.
int PrintedPort(const fs::path& output) {
  std::smatch m;
  const std::string text = ReadFile(output);
  if (!std::regex_search(text, m, std::regex("dashboard on http://127\\.0\\.0\\.1:([0-9]+)/"))) return 0;
  return std::stoi(m[1].str());
}

int WaitForPort(const fs::path& output, ChildProcess& child) {
  for (int i = 0; i < 600 && child.running(); ++i) {
    if (int port = PrintedPort(output)) return port;
    child.Poll();
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  return PrintedPort(output);
}

TEST(DashboardBrowserTest, ThePageShowsALiveRunsCurveUpdatesAndServesTheFinishedFolder) {
  if (Chromium().empty()) GTEST_SKIP() << "SKIP: chromium is not installed (tests/install-test-deps.sh installs it)";
  const fs::path root = fs::path(::testing::TempDir()) / ("dashboard_browser_" + std::to_string(getpid()));
  fs::remove_all(root);
  fs::create_directories(root);
  const fs::path run_dir = root / "run";
  const Browser browser(root / "chromium-profile");

  auto srics_run = [](const std::string& port, const fs::path& dir) {
    std::vector<std::string> argv = {
        SRICS_LAUNCHER, "run",    std::string(SRICS_SOURCE_DIR) + "/deploy/configs/rearrange-1-cpu.yaml",
        "--in-process", "--http", port,
        "--display",    "plain",  "--run-dir",
        dir.string()};
    for (const std::string& o : kShortRun) argv.insert(argv.end(), {"--set", o});
    return argv;
  };
  ChildProcess run = ChildProcess::Spawn(srics_run("0", run_dir), {.output_file = (root / "run.out").string()});
  const int port = WaitForPort(root / "run.out", run);
  ASSERT_GT(port, 0) << ReadFile(root / "run.out");
  const std::string url = "http://127.0.0.1:" + std::to_string(port) + "/";

  // a taken port: exit code 2, a message naming it, and no run folder made
  {
    ChildProcess second = ChildProcess::Spawn(srics_run(std::to_string(port), root / "second"),
                                              {.output_file = (root / "second.out").string()});
    const auto status = second.WaitFor(std::chrono::seconds(60));
    ASSERT_TRUE(status);
    EXPECT_EQ(status->code, 2) << ReadFile(root / "second.out");
    EXPECT_FALSE(status->signaled);
    EXPECT_THAT(ReadFile(root / "second.out"), HasSubstr("127.0.0.1:" + std::to_string(port)));
    EXPECT_THAT(ReadFile(root / "second.out"), HasSubstr("in use"));
    EXPECT_FALSE(fs::exists(root / "second"));
  }

  // wait for the first evaluation of a trained policy, then load the page
  ASSERT_TRUE(WaitFor(port, std::chrono::seconds(240), [](const Json& doc) {
    return doc["runs"].size() == 1 && doc["runs"][0]["evals"].size() >= 1;
  })) << ReadFile(root / "run.out");
  const std::string first = browser.DumpDom(url);
  ASSERT_THAT(first, HasSubstr("id=\"curve\"")) << first.substr(0, 2000);
  EXPECT_GE(CurvePoints(first), 1) << first;
  EXPECT_THAT(first, HasSubstr("class=\"series passive-object\""));  // the passive policy's line
  EXPECT_THAT(first, HasSubstr("id=\"graph-svg\""));                 // the graph is drawn
  EXPECT_THAT(first, HasSubstr("class=\"health alive\""));           // the node table
  const int64_t steps_first = EnvStepsShown(first);
  ASSERT_GT(steps_first, 0) << first.substr(0, 3000);

  // later: more env steps on the page, and more points on the curve once an evaluation came
  ASSERT_TRUE(WaitFor(port, std::chrono::seconds(240),
                      [&](const Json& doc) { return doc["runs"][0]["env_steps"].as<int64_t>() > steps_first + 400; }));
  const std::string second = browser.DumpDom(url);
  const int64_t steps_second = EnvStepsShown(second);
  EXPECT_GT(steps_second, steps_first);
  EXPECT_GE(CurvePoints(second), CurvePoints(first));
  browser.Screenshot(url, root / "dashboard.png");
  const std::string png = ReadFile(root / "dashboard.png");
  EXPECT_GT(png.size(), 20000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");

  // Ctrl-C: the run stops as interrupted
  run.Signal(SIGINT);
  const auto status = run.WaitFor(std::chrono::seconds(120));
  ASSERT_TRUE(status);
  EXPECT_EQ(status->code, 130);

  // the stopped run's folder, served by srics-monitor: the same curve from eval.csv
  ChildProcess monitor =
      ChildProcess::Spawn({SRICS_MONITOR, "--run-dir", run_dir.string(), "--http", "0", "--for", "60"},
                          {.output_file = (root / "monitor.out").string()});
  const int monitor_port = WaitForPort(root / "monitor.out", monitor);
  ASSERT_GT(monitor_port, 0) << ReadFile(root / "monitor.out");
  const std::string folder_page = browser.DumpDom("http://127.0.0.1:" + std::to_string(monitor_port) + "/");
  const auto json_line = Capture(std::string(SRICS_MONITOR) + " --run-dir " + run_dir.string() + " --json --once");
  const Json doc = Json::Parse(json_line);
  const size_t evals = doc["runs"][0]["evals"].size();
  EXPECT_GE(evals, 2u);
  EXPECT_EQ(CurvePoints(folder_page), static_cast<int>(evals));
  EXPECT_THAT(folder_page, HasSubstr("run folder"));
  EXPECT_EQ(EnvStepsShown(folder_page), doc["runs"][0]["env_steps"].as<int64_t>());
  monitor.Signal(SIGINT);
  EXPECT_TRUE(monitor.WaitFor(std::chrono::seconds(30)));
  fs::remove_all(root / "chromium-profile");
  if (!HasFailure()) fs::remove_all(root);  // else the outputs and the screenshot stay for a look
}

}  // namespace
}  // namespace srics::dashboard
