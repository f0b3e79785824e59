#include "deploy/dashboard/server.h"

#include <httplib.h>
#include <sys/socket.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "deploy/dashboard/episode_media.h"
#include "deploy/dashboard/web_assets.h"

namespace srics::dashboard {
namespace {

namespace fs = std::filesystem;

std::string ContentType(const std::string& path) {
  if (path.ends_with(".gif")) return "image/gif";
  if (path.ends_with(".mp4")) return "video/mp4";
  if (path.ends_with(".png")) return "image/png";
  return "application/octet-stream";
}

}  // namespace

int ParseHttpPort(const std::string& text) {
  char* end = nullptr;
  errno = 0;
  const long value = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno != 0 || value < 0 || value > 65535)
    throw std::invalid_argument("--http expects a port number 0-65535 (0: any free port), got '" + text + "'");
  return static_cast<int>(value);
}

HttpServer::HttpServer(ServerOptions options)
    : options_(std::move(options)), server_(std::make_unique<httplib::Server>()) {
  // httplib's default also sets SO_REUSEPORT, with which a second server binds the same port
  // and the two share its connections: only SO_REUSEADDR here, so a taken port is an error
  server_->set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  });
  const int threads = std::max(1, options_.threads);
  server_->new_task_queue = [threads] { return new httplib::ThreadPool(static_cast<size_t>(threads)); };
  // a browser keeps its connections open and each holds a request thread while it does: let
  // idle ones go soon, so a page's parallel requests never wait long for a thread
  server_->set_keep_alive_max_count(20);
  server_->set_keep_alive_timeout(1);
  server_->set_read_timeout(std::chrono::seconds(5));
  server_->set_write_timeout(std::chrono::seconds(5));
  auto asset = [](const char* type, const char* text) {
    return [type, text](const httplib::Request&, httplib::Response& response) {
      response.set_header("Cache-Control", "no-cache");
      response.set_content(text, type);
    };
  };
  server_->Get("/", asset("text/html; charset=utf-8", kIndexHtml));
  server_->Get("/index.html", asset("text/html; charset=utf-8", kIndexHtml));
  server_->Get("/dashboard.js", asset("text/javascript; charset=utf-8", kDashboardJs));
  server_->Get("/dashboard.css", asset("text/css; charset=utf-8", kDashboardCss));
  server_->Get("/api/state", [this](const httplib::Request&, httplib::Response& response) {
    response.set_header("Cache-Control", "no-store");
    const std::string document = Document();
    if (document.empty()) {
      response.status = 503;
      response.set_content("{\"error\":\"no state yet\"}", "application/json");
      return;
    }
    response.set_content(document, "application/json");
  });
  server_->Get(R"(/media/(.+))", [this](const httplib::Request& request, httplib::Response& response) {
    const std::string relative = request.matches[1];
    const std::string dir = RunDir();
    std::ifstream in;
    if (!dir.empty() && IsEpisodeMediaPath(relative)) in.open(fs::path(dir) / relative, std::ios::binary);
    if (!in.is_open() || !in) {
      response.status = 404;
      response.set_content("not found\n", "text/plain");
      return;
    }
    std::ostringstream bytes;
    bytes << in.rdbuf();
    // the page asks for a new episode by another URL (?t=<its time>): frames played in a loop
    // come from the browser's cache
    response.set_header("Cache-Control", "max-age=300");
    response.set_content(bytes.str(), ContentType(relative).c_str());
  });

  errno = 0;
  if (options_.port == 0) {
    port_ = server_->bind_to_any_port(options_.bind);
  } else if (server_->bind_to_port(options_.bind, options_.port)) {
    port_ = options_.port;
  }
  if (port_ <= 0) {
    const int error = errno;
    std::string reason = error == EADDRINUSE
                             ? "the port is in use (another dashboard or program: choose another --http PORT)"
                         : error != 0 ? std::strerror(error)
                                      : "not an address of this host?";
    throw BindError("--http " + std::to_string(options_.port) + ": cannot listen on " + options_.bind + ":" +
                    std::to_string(options_.port) + ": " + reason);
  }
  thread_ = std::thread([this] {
    server_->listen_after_bind();
    listening_done_ = true;
  });
}

HttpServer::~HttpServer() {
  // stop() acts only on a server that is running: wait until the thread listens (or gave up)
  while (!server_->is_running() && !listening_done_) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  server_->stop();
  thread_.join();
}

void HttpServer::Publish(std::string json) {
  std::lock_guard<std::mutex> lock(mutex_);
  document_ = std::move(json);
}

void HttpServer::SetRunDir(const std::string& dir) {
  std::lock_guard<std::mutex> lock(mutex_);
  options_.run_dir = dir;
}

std::string HttpServer::Document() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return document_;
}

std::string HttpServer::RunDir() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return options_.run_dir;
}

std::string HttpServer::url() const {
  const std::string host = options_.bind == "0.0.0.0" || options_.bind.empty() ? "localhost" : options_.bind;
  return "http://" + host + ":" + std::to_string(port_) + "/";
}

}  // namespace srics::dashboard
