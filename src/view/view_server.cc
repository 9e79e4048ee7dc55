#include "view/view_server.h"

#include <httplib.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <random>
#include <thread>

#include "memloop/errors.h"
#include "memloop/map_export.h"
#include "view/view_assets.h"

namespace memloop {

namespace {

using nlohmann::json;

// A request the API cannot take: 400 with this message.
class BadRequest : public Error {
 public:
  using Error::Error;
};

std::string RandomToken() {
  std::random_device device;
  std::string token;
  const char* hex = "0123456789abcdef";
  for (int i = 0; i < 32; ++i) token += hex[device() % 16];
  return token;
}

std::string LoginName() {
  if (const char* user = std::getenv("USER"); user != nullptr && *user != '\0') return user;
  if (const char* login = getlogin(); login != nullptr) return login;
  return "unknown";
}

void SendJson(httplib::Response& response, const json& body, int status = 200) {
  response.status = status;
  response.set_content(body.dump(), "application/json");
}

void SendError(httplib::Response& response, int status, const std::string& message) {
  SendJson(response, {{"error", message}}, status);
}

long long Number(const httplib::Request& request, const char* name, long long fallback) {
  if (!request.has_param(name)) return fallback;
  try {
    return std::stoll(request.get_param_value(name));
  } catch (const std::exception&) {
    throw BadRequest(std::string("parameter '") + name + "' is not a number: '" +
                     request.get_param_value(name) + "'");
  }
}

// Tokens compared in a time that does not depend on where they differ.
bool SameToken(const std::string& given, const std::string& token) {
  if (given.size() != token.size()) return false;
  unsigned char differ = 0;
  for (size_t i = 0; i < token.size(); ++i) differ |= given[i] ^ token[i];
  return differ == 0;
}

}  // namespace

ViewServer::ViewServer(ViewServerOptions options)
    : options_(std::move(options)),
      view_(options_.map),
      images_(options_.images),
      server_(std::make_unique<httplib::Server>()) {
  if (!options_.poses.empty()) {
    for (const auto& [image, pose] : TrajectoryAtImages(view_.AllImages(), options_.poses)) {
      positions_.push_back({static_cast<double>(image), pose[0], pose[1], pose[2]});
    }
  }
  if (options_.token.empty()) options_.token = RandomToken();
  if (options_.who.empty()) options_.who = LoginName();
  // SO_REUSEADDR only: httplib's default SO_REUSEPORT would let a second server take a port in
  // use, and half the requests would reach each.
  server_->set_socket_options([](socket_t socket) {
    const int yes = 1;
    setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  Route();
}

ViewServer::~ViewServer() = default;

int ViewServer::Bind() {
  const std::string where = options_.listen + ":" + std::to_string(options_.port);
  if (options_.port == 0) {
    port_ = server_->bind_to_any_port(options_.listen);
    if (port_ < 0) throw InputError(where, "cannot listen there (--listen)");
  } else {
    if (!server_->bind_to_port(options_.listen, options_.port)) {
      throw InputError(where,
                       "cannot listen there: the port is in use or the address is not "
                       "this machine's (--port, --listen)");
    }
    port_ = options_.port;
  }
  return port_;
}

void ViewServer::Run() {
  run_started_ = true;
  if (!stop_requested_) server_->listen_after_bind();
  run_ended_ = true;
}

// httplib's stop() does nothing before its accept loop runs: a Stop() that comes first (a Ctrl-C
// right at start) waits for the loop, or keeps Run() from starting it.
void ViewServer::Stop() {
  stop_requested_ = true;
  for (int waited_ms = 0;
       run_started_ && !run_ended_ && !server_->is_running() && waited_ms < 10000; ++waited_ms) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  server_->stop();
}

std::string ViewServer::Address() const {
  const bool v6 = options_.listen.find(':') != std::string::npos;
  const std::string host = v6 ? "[" + options_.listen + "]" : options_.listen;
  return "http://" + (options_.listen == "0.0.0.0" ? std::string("127.0.0.1") : host) + ":" +
         std::to_string(port_) + "/";
}

std::string ViewServer::ReadOnlyReason() const {
  if (options_.read_only) return "opened with --read-only";
  const long writer = MapWriterProcess(options_.map);
  if (writer > 0) return "a run is writing the map (pid " + std::to_string(writer) + ")";
  return "";
}

void ViewServer::Route() {
  httplib::Server& server = *server_;
  // Every handler's error is one JSON line: bad input 400, the map refusing 409.
  server.set_exception_handler(
      [](const httplib::Request&, httplib::Response& response, std::exception_ptr thrown) {
        try {
          std::rethrow_exception(thrown);
        } catch (const DatabaseError& error) {
          SendError(response, 409, error.what());
        } catch (const InputError& error) {
          SendError(response, 400, error.what());
        } catch (const BadRequest& error) {
          SendError(response, 400, error.what());
        } catch (const std::exception& error) {
          SendError(response, 500, error.what());
        }
      });
  for (const ViewerAsset& asset : ViewerAssets()) {
    server.Get(asset.path, [&asset](const httplib::Request&, httplib::Response& response) {
      response.set_content(asset.content.data(), asset.content.size(), asset.type);
    });
  }
  server.Get("/api/summary", [this](const httplib::Request&, httplib::Response& response) {
    view_.ReloadIfChanged();  // a run writing the map: what it has committed since
    json summary = view_.Summary();
    const std::string reason = ReadOnlyReason();
    summary["read_only"] = !reason.empty();
    summary["read_only_reason"] = reason;
    summary["images_folder"] = options_.images;
    SendJson(response, summary);
  });
  server.Get("/api/images", [this](const httplib::Request& request, httplib::Response& response) {
    const long long limit = std::clamp(Number(request, "limit", 100), 1LL, 1000LL);
    SendJson(response, view_.Images(static_cast<int>(Number(request, "session", 0)),
                                    std::max(0LL, Number(request, "offset", 0)), limit));
  });
  server.Get(R"(/api/locations/(-?\d+))", [this](const httplib::Request& request,
                                                 httplib::Response& response) {
    const json location = view_.Location(static_cast<LocationId>(std::stoll(request.matches[1])));
    if (location.is_null()) {
      SendError(response, 404, "the map has no location " + std::string(request.matches[1]));
    } else {
      SendJson(response, location);
    }
  });
  server.Get(
      "/api/loop_closures", [this](const httplib::Request& request, httplib::Response& response) {
        const long long limit = std::clamp(Number(request, "limit", 100), 1LL, 100000LL);
        view_.ReloadIfChanged();
        SendJson(response, view_.LoopClosures(std::max(0LL, Number(request, "offset", 0)), limit));
      });
  server.Get("/api/positions", [this](const httplib::Request&, httplib::Response& response) {
    if (positions_.empty()) {
      SendError(response, 404, "no positions: start memloop view with --poses TRAJECTORY");
    } else {
      SendJson(response, {{"positions", positions_}});
    }
  });
  server.Get("/api/edits", [this](const httplib::Request&, httplib::Response& response) {
    SendJson(response, view_.Edits());
  });
  server.Get("/api/find", [this](const httplib::Request& request, httplib::Response& response) {
    const json found = view_.Find(request.get_param_value("q"));
    if (found.is_null()) {
      SendError(
          response, 404,
          "no image of the map is named '" + request.get_param_value("q") + "' or has that index");
    } else {
      SendJson(response, found);
    }
  });
  const auto image_handler = [this](bool thumbnail) {
    return [this, thumbnail](const httplib::Request& request, httplib::Response& response) {
      if (!images_.enabled()) {
        SendError(response, 404, "no images: start memloop view with --images FOLDER");
        return;
      }
      const std::optional<MapImage> image =
          view_.Image(static_cast<ImageIndex>(std::stoll(request.matches[1])));
      std::optional<std::vector<unsigned char>> bytes;
      if (image) bytes = thumbnail ? images_.Thumbnail(image->name) : images_.Full(image->name);
      if (!bytes) {
        SendError(response, 404,
                  "image " + std::string(request.matches[1]) + " (" +
                      (image ? "'" + image->name + "'" : "not in the map") + ") is not in " +
                      options_.images);
        return;
      }
      response.set_header("Cache-Control", "max-age=3600");
      response.set_content(reinterpret_cast<const char*>(bytes->data()), bytes->size(),
                           "image/jpeg");
    };
  };
  server.Get(R"(/api/thumbnails/(\d+))", image_handler(true));
  server.Get(R"(/api/images/(\d+))", image_handler(false));
  server.Post("/api/edits", [this](const httplib::Request& request, httplib::Response& response) {
    if (!SameToken(request.get_header_value("X-Memloop-Token"), options_.token)) {
      SendError(response, 403,
                "an edit needs the token memloop view printed at start (header X-Memloop-Token)");
      return;
    }
    if (const std::string reason = ReadOnlyReason(); !reason.empty()) {
      SendError(response, 409, "the map is read-only here: " + reason);
      return;
    }
    const json body = json::parse(request.body, nullptr, false);
    if (!body.is_object() || !body.contains("action") || !body["action"].is_string()) {
      SendError(response, 400, "an edit is a JSON object with an \"action\": reject, add or undo");
      return;
    }
    const std::string action = body["action"];
    const auto number = [&](const char* name) {
      if (!body.contains(name) || !body[name].is_number_integer()) {
        throw BadRequest(action + " needs \"" + name + "\", an integer");
      }
      return body[name].get<long long>();
    };
    LoopClosureEdit edit;
    if (action == "reject") {
      edit = RejectLoopClosure(options_.map, static_cast<ImageIndex>(number("query_image")),
                               static_cast<ImageIndex>(number("match_image")), options_.who);
    } else if (action == "add") {
      edit = AddLoopClosure(options_.map, static_cast<ImageIndex>(number("query_image")),
                            static_cast<ImageIndex>(number("match_image")), options_.who);
    } else if (action == "undo") {
      edit = UndoEdit(options_.map, number("edit"), options_.who);
    } else {
      SendError(response, 400, "unknown action '" + action + "': reject, add or undo");
      return;
    }
    view_.Reload();
    SendJson(response, {{"id", edit.id}, {"action", action}, {"who", edit.who}});
  });
}

}  // namespace memloop
