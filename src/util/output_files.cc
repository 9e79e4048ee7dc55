#include "util/output_files.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "memloop/errors.h"

namespace memloop {
namespace {

namespace fs = std::filesystem;

// A path as the file system sees it.
struct Resolved {
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
  fs::path path;  // absolute, every symlink that resolves followed, ".." folded
};

Resolved Resolve(const std::string& text) {
  std::error_code error;
  fs::path path = fs::absolute(text, error);
  if (error) path = text;
  // A dangling symlink is where its target would be created: follow it by hand (weakly_canonical
  // stops at it).
  for (int hops = 0; hops < 40; ++hops) {
    struct stat link {};
    struct stat target {};
    if (lstat(path.c_str(), &link) != 0 || !S_ISLNK(link.st_mode)) break;
    if (stat(path.c_str(), &target) == 0) break;
    const fs::path next = fs::read_symlink(path, error);
    if (error) break;
    path = next.is_absolute() ? next : path.parent_path() / next;
  }
  Resolved resolved;
  struct stat info {};
  if (stat(path.c_str(), &info) == 0) {
    resolved.exists = true;
    resolved.device = info.st_dev;
    resolved.inode = info.st_ino;
  }
  resolved.path = fs::weakly_canonical(path, error);
  if (error) resolved.path = path.lexically_normal();
  return resolved;
}

bool SameFile(const Resolved& a, const Resolved& b) {
  if (a.exists != b.exists) return false;
  return a.exists ? a.device == b.device && a.inode == b.inode : a.path == b.path;
}

// Whether `output` is, or would be created as, a file directly in the folder `folder`.
bool InFolder(const Resolved& output, const Resolved& folder) {
  if (output.path.parent_path() == folder.path) return true;
  if (!output.exists) return false;
  std::error_code error;  // a hard link elsewhere to one of the folder's files
  for (const auto& entry : fs::directory_iterator(folder.path, error)) {
    struct stat info {};
    if (stat(entry.path().c_str(), &info) == 0 && info.st_dev == output.device &&
        info.st_ino == output.inode) {
      return true;
    }
  }
  return false;
}

[[noreturn]] void Refuse(const NamedPath& output, const NamedPath& other) {
  const std::string named = other.path == output.path ? "" : " (" + other.path + ")";
  throw InputError(output.path, "is also " + other.role + named + ": give " + output.role +
                                    " another file (it would be overwritten)");
}

std::string Reason(int error) { return error != 0 ? std::strerror(error) : "unknown error"; }

}  // namespace

void CheckOutputsAreNotInputs(const std::vector<NamedPath>& inputs,
                              const std::vector<NamedPath>& given_outputs) {
  std::vector<NamedPath> outputs;
  for (const NamedPath& output : given_outputs) {
    if (!output.path.empty()) outputs.push_back(output);
  }
  std::vector<Resolved> resolved_outputs;
  for (const NamedPath& output : outputs) resolved_outputs.push_back(Resolve(output.path));
  for (size_t i = 0; i < outputs.size(); ++i) {
    for (size_t j = 0; j < i; ++j) {
      if (SameFile(resolved_outputs[i], resolved_outputs[j])) Refuse(outputs[i], outputs[j]);
    }
  }
  for (const NamedPath& input : inputs) {
    if (input.path.empty()) continue;
    const Resolved resolved_input = Resolve(input.path);
    for (size_t i = 0; i < outputs.size(); ++i) {
      if (SameFile(resolved_outputs[i], resolved_input)) Refuse(outputs[i], input);
      if (input.every_file_read && InFolder(resolved_outputs[i], resolved_input)) {
        throw InputError(outputs[i].path, "is in " + input.role + " (" + input.path +
                                              "), whose every file is read as an image: write " +
                                              outputs[i].role + " elsewhere");
      }
    }
  }
}

void WriteWholeFile(const std::string& path, const std::string& what,
                    const std::function<void(const std::string& temporary_path)>& write,
                    bool sync) {
  struct stat existing {};
  const bool exists = stat(path.c_str(), &existing) == 0;
  if (exists && S_ISDIR(existing.st_mode)) throw InputError(path, "is a folder, not " + what);
  if (exists && !S_ISREG(existing.st_mode)) {  // a device or a pipe: nothing to replace
    write(path);
    return;
  }
  const fs::path target(path);
  const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
  const std::string extension = target.extension().string();
  std::string pattern =
      (folder / ("." + target.stem().string() + ".partial-XXXXXX" + extension)).string();
  const int fd = mkstemps(pattern.data(), static_cast<int>(extension.size()));
  if (fd < 0) {
    const int error = errno;
    std::error_code ignored;
    if (!fs::is_directory(folder, ignored)) {
      throw InputError(
          path, "cannot write " + what + ": the folder " + folder.string() + " does not exist");
    }
    throw InputError(path, "cannot write " + what + " in the folder " + folder.string() + " (" +
                               Reason(error) + ")");
  }
  // The new file gets the old one's permissions, or a new file's (0666 less the umask).
  const mode_t mask = umask(0);
  umask(mask);
  fchmod(fd, exists ? existing.st_mode & 07777 : 0666 & ~mask);
  close(fd);
  const std::string temporary = pattern;
  try {
    write(temporary);
    if (sync) {
      const int sync_fd = open(temporary.c_str(), O_RDONLY | O_CLOEXEC);
      const bool synced = sync_fd >= 0 && fsync(sync_fd) == 0;
      const int sync_error = errno;
      if (sync_fd >= 0) close(sync_fd);
      if (!synced) {
        throw InputError(path, "cannot write " + what + " (" + Reason(sync_error) + ")");
      }
    }
    if (std::rename(temporary.c_str(), path.c_str()) != 0) {
      throw InputError(path, "cannot replace " + what + " (" + Reason(errno) + ")");
    }
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
}

void WriteWholeFile(const std::string& path, const std::string& what, const std::string& text) {
  WriteWholeFile(path, what, [&](const std::string& temporary) {
    const int fd = open(temporary.c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
    if (fd < 0) throw InputError(path, "cannot write " + what + " (" + Reason(errno) + ")");
    size_t done = 0;
    while (done < text.size()) {
      const ssize_t wrote = ::write(fd, text.data() + done, text.size() - done);
      if (wrote < 0 && errno == EINTR) continue;
      if (wrote <= 0) {
        const int error = wrote < 0 ? errno : ENOSPC;
        close(fd);
        throw InputError(path, "cannot write " + what + " (" + Reason(error) + ")");
      }
      done += static_cast<size_t>(wrote);
    }
    if (close(fd) != 0) throw InputError(path, "cannot write " + what + " (" + Reason(errno) + ")");
  });
}

}  // namespace memloop
