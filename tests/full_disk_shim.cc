// A full disk for one file, for tests (LD_PRELOAD): writes to the file named by FULL_DISK_FILE
// (its canonical path), or to any file of the folder FULL_DISK_FOLDER, fail with ENOSPC past
// FULL_DISK_BYTES, the last one cut short, as a full
// file system does. Every other file is written as usual: the map's, unlike under RLIMIT_FSIZE
// (which limits every file of the process, and the map outgrows a CSV long before).
#include <dlfcn.h>
#include <limits.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

using WriteFunction = ssize_t (*)(int, const void*, size_t);

WriteFunction RealWrite() {
  static WriteFunction real = reinterpret_cast<WriteFunction>(dlsym(RTLD_NEXT, "write"));
  return real;
}

// The file named by FULL_DISK_FILE, or any file directly in FULL_DISK_FOLDER (canonical paths).
bool IsFullFile(int fd) {
  const char* target = std::getenv("FULL_DISK_FILE");
  const char* folder = std::getenv("FULL_DISK_FOLDER");
  if (target == nullptr && folder == nullptr) return false;
  char link[64];
  char path[PATH_MAX];
  std::snprintf(link, sizeof(link), "/proc/self/fd/%d", fd);
  const ssize_t length = readlink(link, path, sizeof(path) - 1);
  if (length < 0) return false;
  path[length] = '\0';
  if (target != nullptr && std::strcmp(path, target) == 0) return true;
  if (folder == nullptr) return false;
  const size_t size = std::strlen(folder);
  return std::strncmp(path, folder, size) == 0 && path[size] == '/' &&
         std::strchr(path + size + 1, '/') == nullptr;
}

}  // namespace

extern "C" ssize_t write(int fd, const void* buffer, size_t count) {
  if (IsFullFile(fd)) {
    const char* bytes = std::getenv("FULL_DISK_BYTES");
    const off_t limit = bytes ? std::atoll(bytes) : 0;
    const off_t at = lseek(fd, 0, SEEK_CUR);
    if (at >= limit) {
      errno = ENOSPC;
      return -1;
    }
    if (at + static_cast<off_t>(count) > limit) count = static_cast<size_t>(limit - at);
  }
  return RealWrite()(fd, buffer, count);
}

// libstdc++ writes large outputs with writev: the same rule, through write() above.
extern "C" ssize_t writev(int fd, const struct iovec* vectors, int count) {
  ssize_t total = 0;
  for (int i = 0; i < count; ++i) {
    const ssize_t written = write(fd, vectors[i].iov_base, vectors[i].iov_len);
    if (written < 0) return total > 0 ? total : -1;
    total += written;
    if (static_cast<size_t>(written) < vectors[i].iov_len) break;
  }
  return total;
}
