#include "rove/viz/viewer_server.h"

#include <fmt/format.h>
#include <httplib.h>
#include <sys/socket.h>

#include <atomic>
#include <chrono>
#include <map>
#include <thread>

#include "rove/core/check.h"
#include "rove/core/error.h"
#include "rove/core/interrupt.h"

namespace rove {

struct ViewerServer::Impl {
  httplib::Server server;
  std::thread thread;
  std::string host;
  int port = 0;
  std::atomic<bool> stopped{false};
  std::atomic<std::uint64_t> requests{0};
  std::string page;
  std::vector<std::uint8_t> glb;
  std::map<std::string, std::string, std::less<>> scripts;  // "/three/<file>", "/viewer.js"
};

ViewerServer::ViewerServer(std::vector<std::uint8_t> glb, const ViewerServerOptions& options)
    : impl_(std::make_unique<Impl>()) {
  ROVE_CHECK_MSG(options.port >= 0 && options.port <= 65535, "port {} is outside 0-65535", options.port);
  Impl& s = *impl_;
  s.host = options.host;
  s.glb = std::move(glb);
  s.page = served_page(options.page);
  for (std::string_view f : three_script_files()) {
    s.scripts.emplace("/three/" + std::string(f), read_three_script(options.page.three_dir, f));
  }
  s.scripts.emplace("/viewer.js", std::string(viewer_script()));
  // SO_REUSEADDR only: a port another program listens on must be refused,
  // not shared (httplib's default SO_REUSEPORT would share it).
  s.server.set_socket_options([](socket_t sock) {
    int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  s.server.Get("/", [&s](const httplib::Request&, httplib::Response& res) {
    ++s.requests;
    res.set_content(s.page, "text/html; charset=utf-8");
  });
  s.server.Get("/scene.glb", [&s](const httplib::Request&, httplib::Response& res) {
    ++s.requests;
    res.set_content(reinterpret_cast<const char*>(s.glb.data()), s.glb.size(), "model/gltf-binary");
  });
  s.server.Get(R"(/(three/.+|viewer\.js))", [&s](const httplib::Request& req, httplib::Response& res) {
    ++s.requests;
    const auto it = s.scripts.find(req.path);
    if (it == s.scripts.end()) {
      res.status = 404;
      return;
    }
    res.set_content(it->second, "text/javascript; charset=utf-8");
  });
  const std::string where = fmt::format("{}:{}", options.host, options.port);
  if (options.port == 0) {
    s.port = s.server.bind_to_any_port(options.host);
    if (s.port < 0) throw ResourceError(fmt::format("cannot listen on {}: no free port", options.host));
  } else {
    if (!s.server.bind_to_port(options.host, options.port)) {
      throw ResourceError(fmt::format("cannot listen on {}: the port is in use or not allowed (choose "
                                      "another with --port)",
                                      where));
    }
    s.port = options.port;
  }
  s.thread = std::thread([&s] { s.server.listen_after_bind(); });
  // stop() only reaches a server that is running: wait until it is.
  while (!s.server.is_running()) std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

ViewerServer::~ViewerServer() { stop(); }

int ViewerServer::port() const noexcept { return impl_->port; }

std::string ViewerServer::url() const {
  const std::string host = impl_->host == "127.0.0.1" ? "localhost" : impl_->host;
  return fmt::format("http://{}:{}/", host, impl_->port);
}

void ViewerServer::wait() {
  while (!impl_->stopped) {
    if (interrupted()) {
      stop();
      throw_if_interrupted();
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
}

void ViewerServer::stop() {
  if (impl_->stopped.exchange(true)) return;
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

std::uint64_t ViewerServer::requests() const noexcept { return impl_->requests; }

}  // namespace rove
