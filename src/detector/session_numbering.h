// Which session new images join and where its images start (multi-session maps, MapMode): a new
// session's images must come after every earlier session's, and a resumed map goes on in its last
// session.
#pragma once

#include <vector>

#include "memloop/map_info.h"
#include "memloop/types.h"

namespace memloop {

class SessionNumbering {
 public:
  // A resumed map goes on in its last session; `last_image` is the map's last image. A map made
  // before images were recorded (no sessions) is session 0 from image 0.
  void Resume(const std::vector<MapSession>& sessions, ImageIndex last_image);
  // MapMode::kNewSession: images after `last_image` (the map's last) start session id() + 1.
  void StartNew(ImageIndex last_image);
  // Throws InputError when image `index` (kNoImage: numbered by the detector) does not come after
  // the earlier sessions' images.
  void CheckImage(ImageIndex index) const;
  // Image `index` joins the session: the first one is its first image.
  void Record(ImageIndex index);

  int id() const { return id_; }
  // The session's first image, or `next_image` when it has none yet.
  ImageIndex first_image(ImageIndex next_image) const {
    return first_image_ != kNoImage ? first_image_ : next_image;
  }

 private:
  int id_ = 0;
  ImageIndex first_image_ = kNoImage;                  // kNoImage before it has one
  ImageIndex earlier_sessions_last_image_ = kNoImage;  // new images must come after it
};

}  // namespace memloop
