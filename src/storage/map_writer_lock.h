// One writer per map: a process that opens a map to write it holds an exclusive lock (flock) on
// "<map>-lock" beside it, holding its pid, until it closes the map. Another process that wants
// to write the map is refused naming that pid, and one that reads it knows it reads what the
// writer has committed so far (SQLite's write-ahead log lets it), not a closed map. flock locks
// go with their process: a writer killed with -9 holds nothing, and its lock file is reused.
// A separate file, not the map: closing any descriptor of the map in a process would drop the
// POSIX locks SQLite holds on it there.
#pragma once

#include <string>

namespace memloop {

class MapWriterLock {
 public:
  // Throws DatabaseError naming the map: written by another process (its pid), or a folder where
  // the lock file (and so the map's -wal and -shm) cannot be created, saying why.
  explicit MapWriterLock(const std::string& map_path);
  // Removes the lock file if this created it or Adopt() was called: a refused open leaves the
  // file a killed writer left, as it leaves every other file.
  ~MapWriterLock();
  MapWriterLock(const MapWriterLock&) = delete;
  MapWriterLock& operator=(const MapWriterLock&) = delete;

  // The map is open to write: the lock file (one a killed writer left too) is this writer's,
  // holds its pid, and is removed when it closes.
  void Adopt();

 private:
  void WritePid();

  std::string path_;
  int fd_ = -1;
  bool created_ = false;
};

// "<map>-lock".
std::string MapLockPath(const std::string& map_path);

// Whether the map is open to write now, by another process or by this one (a lock this process
// holds for a map it has not opened yet does not count): SQLite must then read its log.
bool MapOpenToWrite(const std::string& map_path);

// Throws DatabaseError "<map>: cannot <use>: the map is being written by another process (pid
// N); ..." when one is (MapWriterProcess, map_info.h). `use`: "resume", "localize against it".
void ThrowIfBeingWritten(const std::string& map_path, const std::string& use);

}  // namespace memloop
