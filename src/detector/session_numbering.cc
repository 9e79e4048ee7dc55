#include "detector/session_numbering.h"

#include <string>

#include "memloop/errors.h"

namespace memloop {

void SessionNumbering::Resume(const std::vector<MapSession>& sessions, ImageIndex last_image) {
  earlier_sessions_last_image_ = kNoImage;
  if (sessions.empty()) {
    id_ = 0;
    first_image_ = last_image == kNoImage ? kNoImage : 0;
    return;
  }
  id_ = sessions.back().id;
  // The first session starts at image 0, whatever it recorded (a map upgraded from format 4
  // records its images from the upgrade on).
  first_image_ = id_ == 0 ? 0 : sessions.back().first_image;
  if (sessions.size() > 1) earlier_sessions_last_image_ = sessions[sessions.size() - 2].last_image;
}

void SessionNumbering::StartNew(ImageIndex last_image) {
  earlier_sessions_last_image_ = last_image;
  first_image_ = kNoImage;
  ++id_;
}

void SessionNumbering::CheckImage(ImageIndex index) const {
  if (index == kNoImage || index > earlier_sessions_last_image_) return;
  throw InputError("image " + std::to_string(index),
                   "a new session's images come after the earlier sessions' (the last is image " +
                       std::to_string(earlier_sessions_last_image_) + ")");
}

void SessionNumbering::Record(ImageIndex index) {
  if (first_image_ == kNoImage) first_image_ = index;
}

}  // namespace memloop
