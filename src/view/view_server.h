// `memloop view`'s web server (cpp-httplib): the viewer's page and its JSON API over one map.
// Reading needs nothing; an edit needs the token the server was started with (header
// X-Memloop-Token), so that no other page the browser opens can write the map: a page of another
// origin cannot send that header without a preflight this server never grants.
//
//   GET  /                          the viewer (HTML, JavaScript and CSS built in: works offline)
//   GET  /api/summary               the map: sessions, counts, parameters, whether edits are
//   allowed GET  /api/images?session=S&offset=O&limit=L   a session's images, a page at a time GET
//   /api/locations/ID          a location: images, words, links, its loop closures GET
//   /api/loop_closures?offset=O&limit=L      detected (some rejected) and added ones GET /api/edits
//   the edits, in the order made GET  /api/find?q=NAME_OR_INDEX  an image GET
//   /api/thumbnails/IMAGE, /api/images/IMAGE   JPEG (with --images) POST /api/edits {"action":
//   "reject"|"add", "query_image", "match_image"}
//                                   or {"action": "undo", "edit": ID}: 403 without the token,
//                                   409 when read-only, 400 naming what is wrong
#pragma once

#include <array>
#include <atomic>
#include <memory>
#include <string>

#include "view/image_source.h"
#include "view/map_view.h"

namespace httplib {
class Server;
}

namespace memloop {

struct ViewServerOptions {
  std::string map;
  std::string images;  // folder of the map's images ("" for none)
  std::string poses;   // TUM trajectory of the images' time stamps ("" for none)
  std::string listen = "127.0.0.1";
  int port = 0;  // 0: any free port
  bool read_only = false;
  std::string token;  // "" : a random one
  std::string who;    // the edits' author ("": the login name)
};

class ViewServer {
 public:
  // Throws DatabaseError / InputError naming the map or the images folder.
  explicit ViewServer(ViewServerOptions options);
  ~ViewServer();

  // Binds the address; throws InputError naming it when it cannot (a port in use). Returns the
  // port.
  int Bind();
  // Serves until Stop() (another thread, or a signal handler's thread).
  void Run();
  void Stop();

  const std::string& token() const { return options_.token; }
  // http://ADDRESS:PORT/
  std::string Address() const;
  // Why edits are refused now ("" when they are not): --read-only, or a run writing the map.
  std::string ReadOnlyReason() const;

 private:
  void Route();

  ViewServerOptions options_;
  MapView view_;
  ImageSource images_;
  std::vector<std::array<double, 4>> positions_;  // image, x, y, z
  std::unique_ptr<httplib::Server> server_;
  int port_ = 0;
  std::atomic<bool> run_started_{false};
  std::atomic<bool> stop_requested_{false};
  std::atomic<bool> run_ended_{false};
};

}  // namespace memloop
