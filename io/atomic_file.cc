#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "measure/input_error.h"
#include "io/interrupt.h"

namespace surfreg {
namespace {

// The directory part of `path` ("." for a bare file name).
std::string DirectoryOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  if (slash == std::string::npos) return ".";
  if (slash == 0) return "/";
  return path.substr(0, slash);
}

[[noreturn]] void Fail(const std::string& label, const std::string& what) {
  throw InputError(label + ": " + what);
}

// Unique among this process's temporary files; other processes differ by pid.
std::string TemporaryName(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp-" + std::to_string(getpid()) + "-" + std::to_string(counter++);
}

// Writes all of `data` to `fd`, retrying short writes and EINTR.
bool WriteAll(int fd, std::string_view data) {
  while (!data.empty()) {
    const ssize_t written = ::write(fd, data.data(), data.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    data.remove_prefix(static_cast<std::size_t>(written));
  }
  return true;
}

}  // namespace

bool SameFile(const std::string& a, const std::string& b) {
  struct stat sa, sb;
  return a == b || (::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 && sa.st_dev == sb.st_dev &&
                    sa.st_ino == sb.st_ino);
}

void CheckOutputPath(const std::string& path, const std::string& label) {
  if (path.empty()) Fail(label, "empty file name");
  if (path.back() == '/') Fail(label, "'" + path + "' names a directory, not a file");
  const std::string directory = DirectoryOf(path);
  struct stat info;
  if (::stat(directory.c_str(), &info) != 0) {
    Fail(label, "cannot write '" + path + "': directory '" + directory + "' does not exist (" +
                    std::strerror(errno) + ")");
  }
  if (!S_ISDIR(info.st_mode)) {
    Fail(label, "cannot write '" + path + "': '" + directory + "' is not a directory");
  }
  if (::stat(path.c_str(), &info) == 0 && S_ISDIR(info.st_mode)) {
    Fail(label, "cannot write '" + path + "': it is a directory");
  }
}

void WriteFileAtomically(const std::string& path, std::string_view data, const std::string& label) {
  CheckOutputPath(path, label);
  std::string temporary;
  int fd = -1;
  for (int attempt = 0; fd < 0 && attempt < 100; ++attempt) {
    temporary = TemporaryName(path);
    fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0 && errno != EEXIST) break;
  }
  if (fd < 0) {
    Fail(label, "cannot create a temporary file next to '" + path + "': " + std::strerror(errno));
  }
  const int slot = RegisterTemporary(temporary);  // an interrupted run removes it
  const bool written = WriteAll(fd, data);
  int error = written ? 0 : errno;
  if (::close(fd) != 0 && error == 0) error = errno;  // NFS reports write errors at close
  if (error == 0 && std::rename(temporary.c_str(), path.c_str()) != 0) error = errno;
  if (error != 0) std::remove(temporary.c_str());
  UnregisterTemporary(slot);
  if (error != 0) Fail(label, "cannot write '" + path + "': " + std::strerror(error));
}

}  // namespace surfreg
