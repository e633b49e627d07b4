#pragma once
/// \file
/// A small HTTP server (cpp-httplib) that shows one scene in a browser:
/// `/` the page, `/viewer.js`, `/three/...` the three.js scripts read from
/// Debian's libjs-three when the server starts, `/scene.glb` the scene.
/// Nothing is fetched from the network. It binds to 127.0.0.1 unless told
/// otherwise; over SSH, forward the port (`ssh -L 8080:localhost:8080 host`).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "rove/viz/viewer_page.h"

namespace rove {

/// Options of ViewerServer.
struct ViewerServerOptions {
  /// Address to listen on: 127.0.0.1 (this machine only) by default;
  /// 0.0.0.0 shows the scene to every machine that can reach this one.
  std::string host = "127.0.0.1";
  /// TCP port, 0–65535; 0 lets the system choose a free one (see port()).
  int port = 8080;
  /// The page's options (three.js folder, level of detail).
  ViewerPageOptions page;
};

/// Serves a scene until stopped. Thread-safety: stop() may be called from
/// any thread; the rest from the owning thread.
class ViewerServer {
 public:
  /// Reads the three.js scripts and binds the port; requests are answered
  /// from then on, on a thread of the server's own. Throws IoError if
  /// three.js is missing, ResourceError naming the address when the port is
  /// in use or not allowed, InvalidArgument for a port outside 0–65535.
  ViewerServer(std::vector<std::uint8_t> glb, const ViewerServerOptions& options);
  /// Stops the server and joins its thread.
  ~ViewerServer();
  ViewerServer(const ViewerServer&) = delete;
  ViewerServer& operator=(const ViewerServer&) = delete;

  /// The port bound (the chosen one when the options said 0).
  int port() const noexcept;
  /// http://host:port/ (localhost for 127.0.0.1).
  std::string url() const;
  /// Blocks until stop() or, when the command line installed the handler,
  /// Ctrl-C (rove/core/interrupt.h; then throws rove::Interrupted after the
  /// server stopped).
  void wait();
  /// Stops serving (idempotent).
  void stop();
  /// Requests answered so far.
  std::uint64_t requests() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rove
