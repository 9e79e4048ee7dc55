// memloop's detector: appearance-based loop closure detection under a time limit, with memory
// management (Labbe & Michaud, "Memory Management for Real-Time Appearance-Based Loop Closure
// Detection", IROS 2011). Give it images in acquisition order; each call says whether the image
// closes a loop with a location seen before.
//
// Ownership and lifetime: the detector owns its memory and the LTM database file it creates; the
// file stays after the detector is destroyed and then holds the whole map (the destructor stores
// the locations of STM and WM too).
// Threading: one thread calls Process(); an internal thread writes the LTM.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "memloop/map_info.h"
#include "memloop/options.h"
#include "memloop/result.h"

namespace memloop {

enum class MapMode {
  kNew,     // a new map: the file must not exist or be empty (an existing file is not modified)
  kResume,  // go on with the map in the file from its last checkpoint, in its last session
  // Open the map in the file at its last checkpoint and start a new session in it (multi-session
  // mapping): the earlier sessions' locations stay (LTM, and WM as the checkpoint left it, STM
  // joining WM), the new session's first location is linked to none of them, the filter starts
  // from "a new place", and loop closures link the sessions. Its images are numbered after the
  // map's last image (session_first_image()).
  kNewSession,
};

// What the map records of an image besides its content.
struct ImageInfo {
  // Names the image in results and in the map; kNoImage: the one after the map's last image (0
  // for a new map). A new session's images must come after the earlier sessions' images.
  ImageIndex index = kNoImage;
  std::string name;                 // e.g. its file name; "" when none
  double timestamp = kNoTimestamp;  // seconds (types.h); written to the map and the results
};

class Detector {
 public:
  // Throws ParameterError for invalid options and DatabaseError when `database_path` cannot be
  // used: kNew, it holds something; kResume, it is not a memloop map, is damaged, has no
  // checkpoint (made by an older memloop), or was made with different values of parameters that
  // define the map (ParameterError naming each; see DefinesMap in params.h); any mode, another
  // process is writing it (MapWriterProcess, map_info.h). A refused file is never modified. A map
  // that holds no image yet (a run killed before its first checkpoint) is resumed from its start.
  // Resuming restores STM, WM, the dictionary and the filter as they were at the last checkpoint;
  // images after it are to be given again (last_image() says which). With
  // options.memory.localization, the map at `database_path` must exist, whatever `mode`: it is
  // opened read-only from its last checkpoint, images are matched against it (loop_closure_id names
  // the map's location; location_id is kNoLocation, the image makes none) and nothing is written,
  // Close() included. Retrieval and transfer work as in mapping, in memory.
  Detector(const Options& options, const std::string& database_path, MapMode mode = MapMode::kNew);
  ~Detector();
  Detector(const Detector&) = delete;
  Detector& operator=(const Detector&) = delete;

  // One iteration of the paper's Fig. 1 for an 8-bit gray or BGR image. `image_index` names the
  // image in results and in the database (e.g. its position in a folder); by default the count of
  // images processed so far. Throws InputError for an empty or unsupported image, nothing changed.
  // The resume checkpoint of an image's state is written by the next Process() (or by Flush() or
  // Close()): a caller who stores each result before the next call has a map that is never ahead
  // of what it stored, and calls CloseAtLastCheckpoint() when it could not store one.
  Result Process(const cv::Mat& image, ImageIndex image_index = kNoImage);
  // The same, with the image's name and time stamp, which the map records (MapImage). Throws
  // InputError for an index of a new session that is not after the earlier sessions' images.
  Result Process(const cv::Mat& image, const ImageInfo& info);
  // The same with the image's depth map, registered to it (same size): 16-bit unsigned in
  // millimetres or 32-bit float in metres, 0 (or NaN) where there is no reading; empty: none. With
  // camera.fx..cy set, a loop closure's translation is then metric (Result's geometry, the map).
  // Throws InputError naming "depth" for another type or size, nothing changed.
  Result Process(const cv::Mat& image, const cv::Mat& depth, const ImageInfo& info = {});

  // Writes a checkpoint and waits until it is committed with everything before it: a crash
  // after Flush() loses nothing (memory.checkpoint_interval bounds the loss otherwise).
  void Flush();

  // A fleet's map (a server map with --robot; docs/fleet.md): the places other robots have stored
  // so far join this robot's map now, all of them, instead of memory.fleet_imports an image (a
  // robot joining a fleet, as a map is loaded before a mission). Waits up to `seconds` for each
  // read of the server; throws DatabaseError when it does not answer. Returns how many joined
  // (0 when the map is not a fleet's).
  size_t CatchUpWithFleet(double seconds = 30);
  // The image of the last Process() call; for a resumed map, of the last checkpoint until then.
  // kNoImage before any image.
  ImageIndex last_image() const;
  // Images processed in this map, over every run that resumed it.
  long long images_processed() const;
  // The session new images join (0: the map's first) and its first image (before it has one, the
  // index its first image gets by default: last_image() + 1). A resumed map goes on in its last
  // session.
  int session() const;
  ImageIndex session_first_image() const;
  // Verifies the map's invariants and returns what is wrong (empty: consistent): every link is
  // symmetric and points to a location in memory or LTM; every word of an STM/WM location is in
  // the dictionary with the right reference count; every word of an LTM location is stored in
  // LTM or kept in the dictionary for LTM; the filter's states are exactly WM, each in [0, 1].
  // Reads every LTM location: for tests and debugging, not for every image of a long run.
  std::vector<std::string> CheckConsistency();
  // For tests: holds the LTM writer back (it then commits only when the detector must wait for
  // it). Results must not depend on it; the determinism tests use it.
  void SetWriterHeld(bool held);
  // Stores the STM and WM locations too, writes a checkpoint and commits, so the file holds the
  // whole map and can be resumed. Process() may not be called afterwards. The destructor calls
  // it, but cannot report a failure. After a failed Process() (an exception other than a refused
  // image), nothing more is written: the file stays at its last checkpoint.
  void Close();
  // Closes without storing anything after the last checkpoint written, as a crash would leave
  // the file (resumable from it): for a caller that could not store the last Process() result
  // (e.g. its CSV's disk is full), so that the map does not hold an image its results lack.
  void CloseAtLastCheckpoint();
  const Options& options() const;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

// How far a map's last checkpoint goes: what `memloop run --resume` goes on from.
struct MapProgress {
  MapProgress() { last_session.id = -1; }
  ImageIndex last_image = kNoImage;  // the last image it holds
  long long images_processed = 0;    // over every run that made it
  // Its last session (MapSession::id = -1 for a map made before memloop recorded images).
  MapSession last_session;
};
// Read without changing the file. A map that holds no image yet (a run killed before its first
// checkpoint) gives last_image kNoImage: resumed, it starts from its first image. Throws
// DatabaseError when `path` is not a readable memloop map, or holds locations but no checkpoint.
MapProgress ReadMapProgress(const std::string& path);

// The options a map was made with (its parameter table). Throws DatabaseError when `path` is not
// a readable memloop map. `memloop run --resume` starts from these.
Options ReadMapOptions(const std::string& path);

}  // namespace memloop
