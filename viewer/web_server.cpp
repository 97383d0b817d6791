#define ASIO_STANDALONE
#include "viewer/web_server.hpp"

#include <algorithm>
#include <csignal>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <websocketpp/config/asio_no_tls.hpp>
#include <websocketpp/server.hpp>

namespace swarmform::viewer {

namespace {

using Server = websocketpp::server<websocketpp::config::asio>;
using Hdl = websocketpp::connection_hdl;

constexpr const char* kFoxgloveSubprotocol = "foxglove.websocket.v1";
constexpr std::size_t kMaxBuffered = std::size_t{8} << 20;  // bytes queued to one client
constexpr std::chrono::milliseconds kCloseWait{500};        // stopping: how long clients have to close

// What GET may fetch: the page's files from web_root and the small files of the recording from run_dir (not
// robots.csv: a file is sent whole, and the replay reads robots.csv a tick at a time itself). Nothing else:
// no path from the request reaches the file system.
struct Served {
  const char* path;
  const char* file;
  const char* type;
  bool from_run;
};
constexpr Served kServed[] = {
    {"/", "index.html", "text/html; charset=utf-8", false},
    {"/index.html", "index.html", "text/html; charset=utf-8", false},
    {"/viewer.js", "viewer.js", "text/javascript; charset=utf-8", false},
    {"/viewer.css", "viewer.css", "text/css; charset=utf-8", false},
    {"/run/world.json", "world.json", "application/json", true},
    {"/run/events.jsonl", "events.jsonl", "application/x-ndjson", true},
    {"/run/summary.json", "summary.json", "application/json", true},
    {"/run/floor.png", "floor.png", "image/png", true},  // the floor image's copy (world.json floor.image)
};

bool read_file(const std::string& path, std::string& out) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return false;
  std::ostringstream ss;
  ss << f.rdbuf();
  out = ss.str();
  return true;
}

}  // namespace

struct WebServer::Impl {
  WebServerOptions options;
  Handlers handlers;
  int period_ms = 20;
  Server server;
  std::unique_ptr<asio::steady_timer> timer;
  std::unique_ptr<asio::signal_set> signals;
  std::map<Hdl, std::pair<ClientId, ClientKind>, std::owner_less<Hdl>> clients;
  std::map<ClientId, Hdl> by_id;
  std::set<ClientId> drivers;  // clients that may control the run (may_drive)
  ClientId next_id = 1;
  bool stopping = false;

  void arm() {
    timer->expires_after(std::chrono::milliseconds(period_ms));
    timer->async_wait([this](const asio::error_code& ec) {
      if (ec || stopping) return;
      if (!handlers.every()) {
        stop();
        return;
      }
      arm();
    });
  }

  void stop() {
    if (stopping) return;
    stopping = true;
    if (handlers.stopping) handlers.stopping();
    if (timer) timer->cancel();
    if (signals) signals->cancel();
    websocketpp::lib::error_code ec;
    server.stop_listening(ec);
    for (auto& [hdl, c] : clients)
      server.close(hdl, websocketpp::close::status::going_away, "viewer ends", ec);
    // The last messages (the run's end) and the close frames go out before the loop stops: it stops once
    // every client has closed (the close handler), or after kCloseWait for one that does not answer.
    if (clients.empty() || !timer) {
      server.stop();
      return;
    }
    timer->expires_after(kCloseWait);
    timer->async_wait([this](const asio::error_code&) { server.stop(); });
  }

  void http(Hdl hdl) {
    Server::connection_ptr con = server.get_con_from_hdl(hdl);
    const std::string resource = con->get_resource();
    const std::string path = resource.substr(0, resource.find('?'));
    for (const Served& s : kServed) {
      if (path != s.path) continue;
      std::string body;
      const std::string file = (s.from_run ? options.run_dir : options.web_root) + "/" + s.file;
      if (!read_file(file, body)) {
        con->set_status(websocketpp::http::status_code::not_found);
        con->set_body(std::string("not there (yet): ") + s.file + "\n");
        return;
      }
      con->set_status(websocketpp::http::status_code::ok);
      con->append_header("Content-Type", s.type);
      con->append_header("Cache-Control", "no-store");
      con->set_body(std::move(body));
      return;
    }
    con->set_status(websocketpp::http::status_code::not_found);
    con->set_body("no such page: " + path + "\n");
  }

  bool validate(Hdl hdl) {
    Server::connection_ptr con = server.get_con_from_hdl(hdl);
    const auto& wanted = con->get_requested_subprotocols();
    if (std::find(wanted.begin(), wanted.end(), kFoxgloveSubprotocol) != wanted.end()) {
      con->select_subprotocol(kFoxgloveSubprotocol);
      return true;  // any origin (Foxglove's web app) may read; only may_drive() clients may control
    }
    // The page's protocol can pause and kill: a browser may open it only from our own page. WebSockets have
    // no same-origin rule, so without this any web site the user visits could drive ws://127.0.0.1:8765.
    // Clients that are not browsers send no Origin.
    const std::string origin = con->get_request_header("Origin");
    if (!origin.empty() && origin != "http://" + con->get_request_header("Host")) {
      ++refused_origins;
      if (refused_origins == 1 || refused_origins % 100 == 0) {
        std::cerr << "swarm_viewer: refused " << refused_origins << " WebSocket(s) from another origin, e.g. "
                  << origin.substr(0, 80) << "\n";
      }
      con->set_status(websocketpp::http::status_code::forbidden);
      return false;
    }
    return true;
  }
  std::uint64_t refused_origins = 0;
};

WebServer::WebServer(const WebServerOptions& options, Handlers handlers, int period_ms)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = options;
  m.handlers = std::move(handlers);
  m.period_ms = period_ms;
  m.server.clear_access_channels(websocketpp::log::alevel::all);
  m.server.clear_error_channels(websocketpp::log::elevel::all);
  m.server.set_error_channels(websocketpp::log::elevel::fatal);
  m.server.init_asio();
  m.server.set_reuse_addr(true);
  m.server.set_http_handler([&m](Hdl h) { m.http(h); });
  m.server.set_validate_handler([&m](Hdl h) { return m.validate(h); });
  m.server.set_open_handler([&m](Hdl h) {
    Server::connection_ptr con = m.server.get_con_from_hdl(h);
    const ClientKind kind =
        con->get_subprotocol() == kFoxgloveSubprotocol ? ClientKind::Foxglove : ClientKind::Page;
    const ClientId id = m.next_id++;
    m.clients[h] = {id, kind};
    // The page's rule for driving the run: no Origin (not a browser) or our own page's.
    const std::string origin = con->get_request_header("Origin");
    const auto& extra = m.options.control_origins;
    if (origin.empty() || origin == "http://" + con->get_request_header("Host") ||
        (kind == ClientKind::Foxglove && std::find(extra.begin(), extra.end(), origin) != extra.end()))
      m.drivers.insert(id);
    m.by_id[id] = h;
    if (m.handlers.opened) m.handlers.opened(id, kind);
  });
  m.server.set_close_handler([&m](Hdl h) {
    const auto it = m.clients.find(h);
    if (it == m.clients.end()) return;
    const ClientId id = it->second.first;
    m.by_id.erase(id);
    m.drivers.erase(id);
    m.clients.erase(it);
    if (m.handlers.closed) m.handlers.closed(id);
    if (m.stopping && m.clients.empty()) m.server.stop();
  });
  m.server.set_fail_handler([](Hdl) {});
  m.server.set_message_handler([&m](Hdl h, Server::message_ptr msg) {
    const auto it = m.clients.find(h);
    if (it == m.clients.end()) return;
    if (msg->get_opcode() == websocketpp::frame::opcode::text) {
      if (m.handlers.text) m.handlers.text(it->second.first, it->second.second, msg->get_payload());
    } else if (m.handlers.binary) {
      m.handlers.binary(it->second.first, msg->get_payload());
    }
  });
  websocketpp::lib::error_code ec;
  asio::ip::tcp::resolver resolver(m.server.get_io_service());
  const auto endpoints = resolver.resolve(options.host, std::to_string(options.port), ec);
  if (ec || endpoints.empty()) {
    throw std::runtime_error("cannot resolve --host " + options.host + ": " + ec.message());
  }
  m.server.listen(endpoints.begin()->endpoint(), ec);
  if (ec) {
    throw std::runtime_error("cannot listen on " + options.host + ":" + std::to_string(options.port) + ": " +
                             ec.message() + " (another viewer on that port? --view PORT picks another)");
  }
  m.server.start_accept(ec);
  if (ec)
    throw std::runtime_error("cannot accept on port " + std::to_string(options.port) + ": " + ec.message());
  m.timer = std::make_unique<asio::steady_timer>(m.server.get_io_service());
  m.signals = std::make_unique<asio::signal_set>(m.server.get_io_service(), SIGINT, SIGTERM);
  m.signals->async_wait([&m](const asio::error_code& e, int) {
    if (!e) m.stop();
  });
}

WebServer::~WebServer() = default;

void WebServer::run() {
  impl_->arm();
  impl_->server.run();
}

void WebServer::stop() {
  impl_->stop();
}

bool WebServer::may_drive(ClientId client) const {
  return impl_->drivers.count(client) != 0;
}

void WebServer::send_text(ClientId client, const std::string& text) {
  const auto it = impl_->by_id.find(client);
  if (it == impl_->by_id.end()) return;
  websocketpp::lib::error_code ec;
  impl_->server.send(it->second, text, websocketpp::frame::opcode::text, ec);  // a closing client: ignored
}

void WebServer::send_binary(ClientId client, const std::string& bytes) {
  const auto it = impl_->by_id.find(client);
  if (it == impl_->by_id.end()) return;
  websocketpp::lib::error_code ec;
  Server::connection_ptr con = impl_->server.get_con_from_hdl(it->second, ec);
  if (ec || con->get_buffered_amount() > kMaxBuffered) return;  // a slow client loses this message
  impl_->server.send(it->second, bytes, websocketpp::frame::opcode::binary, ec);
}

void WebServer::broadcast_text(ClientKind kind, const std::string& text) {
  for (const auto& [hdl, c] : impl_->clients) {
    if (c.second != kind) continue;
    websocketpp::lib::error_code ec;
    // A client that does not keep up loses frames (the next one replaces it) rather than growing our memory.
    Server::connection_ptr con = impl_->server.get_con_from_hdl(hdl, ec);
    if (ec || con->get_buffered_amount() > kMaxBuffered) continue;
    impl_->server.send(hdl, text, websocketpp::frame::opcode::text, ec);
  }
}

std::size_t WebServer::clients(ClientKind kind) const {
  std::size_t n = 0;
  for (const auto& [hdl, c] : impl_->clients) n += c.second == kind ? 1 : 0;
  return n;
}

std::uint16_t WebServer::port() const {
  websocketpp::lib::error_code ec;
  return impl_->server.get_local_endpoint(ec).port();
}

}  // namespace swarmform::viewer
