#include "libbead/io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>

#include "libbead/core/error.h"

namespace bead {

AtomicFile::AtomicFile(std::string destination) : destination_(std::move(destination)) {
  const std::filesystem::path dest(destination_);
  const std::filesystem::path dir = dest.has_parent_path() ? dest.parent_path() : ".";
  if (!std::filesystem::is_directory(dir))
    throw Error(Located(destination_, "", "cannot write: folder " + dir.string() + " does not exist"));
  std::string pattern = (dir / ("." + dest.filename().string() + ".tmp-XXXXXX")).string();
  const int fd = mkstemp(pattern.data());
  if (fd < 0) throw Error(Located(destination_, "", std::string("cannot create a temporary file: ") + std::strerror(errno)));
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

}  // namespace bead
