#include "storage/map_writer_lock.h"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <mutex>
#include <string>

#include "memloop/errors.h"
#include "memloop/map_info.h"
#include "storage/sql_connection.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

// The pid a lock file holds, 0 when it holds none.
long ReadPid(int fd) {
  char text[32] = {};
  const ssize_t length = pread(fd, text, sizeof(text) - 1, 0);
  return length > 0 ? std::strtol(text, nullptr, 10) : 0;
}

std::string Folder(const std::string& path) {
  const std::string folder = fs::path(path).parent_path().string();
  return folder.empty() ? "." : folder;
}

std::string WrittenBy(long pid, const std::string& use) {
  return "cannot " + use + ": the map is being written by another process" +
         (pid > 0 ? " (pid " + std::to_string(pid) + ")" : std::string()) +
         "; it is sound: " + use + " once that process has ended";
}

// The locks this process holds, by lock file: whether their map is open yet (Adopt()).
std::mutex held_mutex;
std::map<std::string, bool> held_here;

void MarkHeld(const std::string& path, bool open) {
  std::lock_guard<std::mutex> lock(held_mutex);
  held_here[path] = open;
}

}  // namespace

std::string MapLockPath(const std::string& map_path) { return map_path + "-lock"; }

bool MapOpenToWrite(const std::string& map_path) {
  if (IsServerMap(map_path)) return false;
  {
    std::lock_guard<std::mutex> lock(held_mutex);
    const auto held = held_here.find(MapLockPath(map_path));
    if (held != held_here.end()) return held->second;
  }
  return MapWriterProcess(map_path) != 0;
}

MapWriterLock::MapWriterLock(const std::string& map_path) : path_(MapLockPath(map_path)) {
  if (IsServerMap(map_path)) return;  // the server holds a robot's lock (ltm_server_map.cc)
  // A lock file another process unlinked between our open and our lock is not the lock: retry.
  for (int attempt = 0; attempt < 100; ++attempt) {
    fd_ = open(path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
    created_ = fd_ >= 0;
    if (fd_ < 0 && errno == EEXIST) {  // a killed writer's, or a live writer's
      fd_ = open(path_.c_str(), O_RDWR | O_CLOEXEC);
      if (fd_ < 0 && errno == ENOENT) continue;  // removed between the two opens
    }
    if (fd_ < 0) {
      const int error = errno;
      const std::string folder = Folder(map_path);
      if (error == ENOENT) {
        throw DatabaseError(map_path,
                            "cannot create the map: the folder " + folder + " does not exist");
      }
      throw DatabaseError(map_path, "cannot write the map in the folder " + folder + " (" +
                                        std::strerror(error) +
                                        "): a map is written there with its -wal, -shm and "
                                        "-lock files; copy it to a writable folder");
    }
    if (flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      const long pid = ReadPid(fd_);
      close(fd_);
      fd_ = -1;
      throw DatabaseError(map_path, WrittenBy(pid, "write it"));
    }
    struct stat held {};
    struct stat named {};
    if (fstat(fd_, &held) == 0 && stat(path_.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
        held.st_dev == named.st_dev) {
      if (created_) WritePid();
      MarkHeld(path_, false);
      return;
    }
    close(fd_);
    fd_ = -1;
  }
  throw DatabaseError(map_path, WrittenBy(0, "write it"));
}

void MapWriterLock::WritePid() {
  const std::string pid = std::to_string(getpid()) + "\n";
  if (ftruncate(fd_, 0) == 0) {
    [[maybe_unused]] const ssize_t wrote = pwrite(fd_, pid.data(), pid.size(), 0);
  }
}

void MapWriterLock::Adopt() {
  if (fd_ < 0) return;
  if (!created_) WritePid();
  created_ = true;
  MarkHeld(path_, true);
}

MapWriterLock::~MapWriterLock() {
  if (fd_ < 0) return;
  {
    std::lock_guard<std::mutex> lock(held_mutex);
    held_here.erase(path_);
  }
  if (created_) unlink(path_.c_str());  // while locked: a waiter on this inode sees it unlinked
  close(fd_);
}

long MapWriterProcess(const std::string& map_path) {
  if (IsServerMap(map_path)) return 0;
  const std::string path = MapLockPath(map_path);
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return 0;
  long pid = 0;
  if (flock(fd, LOCK_SH | LOCK_NB) != 0) {
    pid = ReadPid(fd);
    if (pid <= 0) pid = -1;  // locked, the pid not written yet
  }
  close(fd);  // a shared lock, if taken, goes with it
  return pid;
}

void ThrowIfBeingWritten(const std::string& map_path, const std::string& use) {
  if (const long pid = MapWriterProcess(map_path); pid != 0) {
    throw DatabaseError(map_path, WrittenBy(pid, use));
  }
}

}  // namespace memloop
