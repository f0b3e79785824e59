#pragma once
// The dashboard's HTTP server (cpp-httplib) on its own thread: the page and its script from
// the program itself (no internet, no files needed at run time), the latest JSON document at
// /api/state, and the run folder's episode media under /media/. The owner publishes a new
// document whenever it likes; requests read the latest one.
//
//   HttpServer server({.bind = "127.0.0.1", .port = 8080, .run_dir = dir});  // listening now
//   server.Publish(DashboardJson(...));                                    // any thread
//
// Routes: GET /  /dashboard.js  /dashboard.css  /api/state  /media/eval/episode-NNN.gif|.mp4
// and /media/eval/episode-NNN/frame-NNNNN.png (IsEpisodeMediaPath; nothing else of the folder).
// Threading: Publish from any thread; the server's own threads answer requests. The
// destructor stops the server and joins its thread.

#include <atomic>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>

namespace httplib {
class Server;
}

namespace srics::dashboard {

// The address cannot be listened on (the port is taken, the address is not this host's, a
// privileged port): a usage error of the program (exit code 2), the message names the address
// and the port.
class BindError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct ServerOptions {
  std::string bind = "127.0.0.1";  // --http-bind
  int port = 0;                    // --http; 0 = any free port (see port())
  std::string run_dir;             // where /media/ files come from ("" = none)
  int threads = 4;                 // request threads (a browser opens several connections)
};

class HttpServer {
 public:
  // Binds and starts listening before it returns. Throws BindError.
  explicit HttpServer(ServerOptions options);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // The document /api/state answers from now on.
  void Publish(std::string json);
  // The folder /media/ serves from (the run folder is known after the server started).
  void SetRunDir(const std::string& dir);

  int port() const { return port_; }
  // "http://127.0.0.1:8080/"
  std::string url() const;

 private:
  std::string Document() const;
  std::string RunDir() const;

  ServerOptions options_;
  std::unique_ptr<httplib::Server> server_;
  std::thread thread_;
  std::atomic<bool> listening_done_{false};
  int port_ = 0;
  mutable std::mutex mutex_;
  std::string document_;
};

// Checks the value of --http: a port in [0, 65535]. Throws std::invalid_argument naming
// the option.
int ParseHttpPort(const std::string& text);

}  // namespace srics::dashboard
