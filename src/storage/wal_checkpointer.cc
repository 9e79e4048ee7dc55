#include "storage/wal_checkpointer.h"

namespace memloop {
namespace {

int OnCommit(void* checkpointer, sqlite3*, const char*, int frames) {
  static_cast<WalCheckpointer*>(checkpointer)->Committed(frames);
  return SQLITE_OK;
}

}  // namespace

WalCheckpointer::WalCheckpointer(const std::string& path, int frames)
    : connection_(path, SQLITE_OPEN_READWRITE), frames_(frames), thread_([this] { Loop(); }) {}

WalCheckpointer::~WalCheckpointer() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void WalCheckpointer::Watch(LtmDatabase& database) { database.OnCommit(&OnCommit, this); }

void WalCheckpointer::Committed(int frames) {
  if (frames < frames_) return;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    due_ = true;
  }
  wake_.notify_all();
}

void WalCheckpointer::SetHeld(bool held) {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    held_ = held;
  }
  wake_.notify_all();
  idle_.notify_all();
}

void WalCheckpointer::WaitIdle() {
  std::unique_lock<std::mutex> lock(mutex_);
  idle_.wait(lock, [this] { return held_ || (!due_ && !running_); });
}

int WalCheckpointer::checkpoints() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return checkpoints_;
}

bool WalCheckpointer::last_was_complete() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return last_complete_;
}

void WalCheckpointer::Loop() {
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return stopping_ || (due_ && !held_); });
    if (stopping_) return;
    due_ = false;
    running_ = true;
    lock.unlock();
    int log_frames = 0, copied_frames = 0;
    const int code = sqlite3_wal_checkpoint_v2(
        connection_.handle(), "main", SQLITE_CHECKPOINT_PASSIVE, &log_frames, &copied_frames);
    // On failure (a full disk) the log still holds every commit: nothing is lost, the next
    // commit over the threshold tries again, and the writer reports the disk when it fails too.
    lock.lock();
    running_ = false;
    ++checkpoints_;
    last_complete_ = code == SQLITE_OK && copied_frames == log_frames;
    idle_.notify_all();
  }
}

}  // namespace memloop
