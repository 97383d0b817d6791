// The viewer's HTTP and WebSocket server on one port (websocketpp on standalone asio, one thread): GET serves
// the page's files and the run directory's recording (a fixed list of names, nothing else), a WebSocket on
// any path speaks the page's JSON protocol, or Foxglove's (`foxglove.websocket.v1`) when the client asks for
// that subprotocol. Everything runs on the one asio thread: `every` is called on a timer.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace swarmform::viewer {

enum class ClientKind { Page, Foxglove };

using ClientId = std::uint64_t;

struct WebServerOptions {
  std::string host = "127.0.0.1";
  std::uint16_t port = 8765;
  std::string web_root;  // the page's files (viewer/web)
  std::string run_dir;   // served under /run/ (world.json, events.jsonl, summary.json)
  // Origins besides this server's whose Foxglove clients may control the run (--control-origin, e.g.
  // https://app.foxglove.dev): the user's choice, as --host 0.0.0.0 is.
  std::vector<std::string> control_origins;
};

class WebServer {
 public:
  struct Handlers {
    std::function<void(ClientId, ClientKind)> opened;
    std::function<void(ClientId)> closed;
    std::function<void(ClientId, ClientKind, const std::string&)> text;  // a text message
    std::function<void(ClientId, const std::string&)> binary;            // a binary message
    // Called every `period_ms` on the server's thread; false ends run().
    std::function<bool()> every;
    // Called once when the server stops (SIGINT/SIGTERM, stop(), `every` false), before the clients are
    // closed: what it sends them is their last message.
    std::function<void()> stopping;
  };

  // Binds the port (throws std::runtime_error naming host:port when it cannot).
  WebServer(const WebServerOptions& options, Handlers handlers, int period_ms);
  ~WebServer();
  WebServer(const WebServer&) = delete;
  WebServer& operator=(const WebServer&) = delete;

  // Serves until `every` returns false or stop() is called (SIGINT/SIGTERM call it).
  void run();
  void stop();
  void send_text(ClientId client, const std::string& text);
  void send_binary(ClientId client, const std::string& bytes);
  // To every client of that kind.
  void broadcast_text(ClientKind kind, const std::string& text);
  std::size_t clients(ClientKind kind) const;
  std::uint16_t port() const;  // the bound port (for --port 0)
  // The client may pause, step and kill: it sent no Origin (not a browser) or this server's own (the page's
  // rule; a Foxglove client from another origin only reads).
  bool may_drive(ClientId client) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace swarmform::viewer
