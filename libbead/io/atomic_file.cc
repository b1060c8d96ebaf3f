#include "libbead/io/atomic_file.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>

#include "libbead/core/error.h"

namespace bead {

namespace {

std::string HostName() {
  char host[256] = {};
  if (gethostname(host, sizeof host - 1) != 0 || host[0] == '\0') return "host";
  std::string name(host);
  for (char& c : name)
    if (c == '-' || c == '/') c = '_';
  return name;
}

// Temporaries of `name` left by a process of this host that is gone (one
// killed mid-write): .<name>.tmp-<host>-<pid>-XXXXXX. Another host's (a
// cluster's shared folder) are left alone: their pid means nothing here.
void RemoveStaleTemporaries(const std::filesystem::path& dir, const std::string& name, const std::string& host) {
  const std::string prefix = "." + name + ".tmp-" + host + "-";
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string file = entry.path().filename().string();
    if (file.compare(0, prefix.size(), prefix) != 0) continue;
    char* end = nullptr;
    const long pid = std::strtol(file.c_str() + prefix.size(), &end, 10);
    if (pid <= 0 || *end != '-') continue;
    if (::kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) std::filesystem::remove(entry.path(), ec);
  }
}

}  // namespace

AtomicFile::AtomicFile(std::string destination) : destination_(std::move(destination)) {
  const std::filesystem::path dest(destination_);
  const std::filesystem::path dir = dest.has_parent_path() ? dest.parent_path() : ".";
  if (!std::filesystem::is_directory(dir))
    throw Error(Located(destination_, "", "cannot write: folder " + dir.string() + " does not exist"));
  const std::string host = HostName();
  RemoveStaleTemporaries(dir, dest.filename().string(), host);
  std::string pattern =
      // (A string appended to, not a literal before one: GCC 12 warns of an
      // overlap in `"." + string`'s insert that cannot happen, -Wrestrict.)
      (dir / (std::string(".").append(dest.filename().string()) + ".tmp-" + host + "-" + std::to_string(::getpid()) +
              "-XXXXXX"))
          .string();
  const int fd = mkstemp(pattern.data());
  if (fd < 0)
    throw Error(Located(destination_, "", std::string("cannot create a temporary file: ") + std::strerror(errno)));
  ::close(fd);
  temp_path_ = pattern;
}

AtomicFile::~AtomicFile() {
  if (!committed_) {
    if (stream_.is_open()) stream_.close();
    std::remove(temp_path_.c_str());
  }
}

std::ofstream& AtomicFile::stream() {
  if (!stream_.is_open()) {
    stream_.open(temp_path_, std::ios::out | std::ios::trunc);
    if (!stream_) throw Error(Located(destination_, "", "cannot open temporary file " + temp_path_));
  }
  return stream_;
}

void AtomicFile::Commit() {
  if (stream_.is_open()) {
    stream_.flush();
    if (!stream_) throw Error(Located(destination_, "", "write failed (disk full?)"));
    stream_.close();
  }
  const int fd = ::open(temp_path_.c_str(), O_RDONLY);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
  // mkstemp creates 0600; results are ordinary files.
  ::chmod(temp_path_.c_str(), 0644);
  if (std::rename(temp_path_.c_str(), destination_.c_str()) != 0)
    throw Error(Located(destination_, "", std::string("cannot replace: ") + std::strerror(errno)));
  committed_ = true;
}

void CheckWritable(const std::string& destination) { AtomicFile probe(destination); }

}  // namespace bead
