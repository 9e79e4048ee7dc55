// memloop view MAP [--images DIR] [--port N] [--listen ADDR] [--read-only]: the map in the
// browser, its loop closures corrected there (src/view/view_server.h).
#include <pthread.h>

#include <csignal>
#include <cstdio>
#include <thread>

#include "commands.h"
#include "view/view_server.h"

namespace memloop::cli {

void AddViewCommand(CLI::App& app) {
  auto options = std::make_shared<ViewServerOptions>();
  CLI::App* view = app.add_subcommand(
      "view",
      "Serve the map to a web browser: sessions, locations with their images, loop closures as a "
      "list and a matrix; reject a loop closure or add one (with the token it prints). Stop with "
      "Ctrl-C");
  view->add_option("map", options->map, "Map database file (--db of a run)")->required();
  view->add_option("--images", options->images,
                   "Folder of the images the map was made from (the input of its run, or a data "
                   "set folder with images/): thumbnails and images on its pages");
  view->add_option("--poses", options->poses,
                   "A TUM trajectory (time tx ty tz qx qy qz qw) of the images' time stamps: the "
                   "map drawn by position, its loop closures between them");
  view->add_option("--port", options->port, "Port to listen on; default: a free one")
      ->check(CLI::Range(0, 65535));
  view->add_option("--listen", options->listen,
                   "Address to listen on; default 127.0.0.1 (this machine only). Edits still "
                   "need the token");
  view->add_flag("--read-only", options->read_only, "Refuse every edit");
  view->callback([options] {
    // Ctrl-C and SIGTERM stop the server between requests: blocked in every thread, awaited by
    // one (an edit is one SQLite transaction: it is written whole or not at all either way).
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
    ViewServer server(*options);
    server.Bind();
    std::printf("memloop view: %s serves %s%s\n", server.Address().c_str(), options->map.c_str(),
                options->read_only ? " (read-only)" : "");
    std::printf("  to edit its loop closures open %s#token=%s\n", server.Address().c_str(),
                server.token().c_str());
    std::printf("  Ctrl-C stops it\n");
    std::fflush(stdout);
    std::thread waiter([&server, &stop_signals] {
      int signal = 0;
      sigwait(&stop_signals, &signal);
      server.Stop();
    });
    server.Run();
    pthread_kill(waiter.native_handle(), SIGTERM);  // Run ended by itself: release the waiter
    waiter.join();
    std::printf("memloop view: stopped\n");
  });
}

}  // namespace memloop::cli
