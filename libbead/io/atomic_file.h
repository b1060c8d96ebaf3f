// AtomicFile: write a result so that the destination holds either its old
// content or the complete new one, never a half-written file. Writes go to
// a temporary file beside the destination; Commit() flushes it to disk and
// renames it over the destination. Destroyed uncommitted, it removes the
// temporary and leaves the destination untouched. A killed process cannot
// remove its temporary: they are named .<name>.tmp-<host>-<pid>-XXXXXX,
// and the next AtomicFile for the same destination removes those of this
// host whose process is gone.
#pragma once

#include <fstream>
#include <string>

namespace bead {

class AtomicFile {
 public:
  explicit AtomicFile(std::string destination);
  ~AtomicFile();
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;

  const std::string& destination() const { return destination_; }
  // Where to write (for libraries that open files by name, such as HDF5).
  const std::string& temp_path() const { return temp_path_; }
  // A text stream on the temporary file, opened on first use.
  std::ofstream& stream();
  void Commit();

 private:
  std::string destination_;
  std::string temp_path_;
  std::ofstream stream_;
  bool committed_ = false;
};

// Checks, before any work, that `destination` can be written as an
// AtomicFile would write it (its folder exists, a temporary can be made
// there); throws bead::Error naming the file and what to fix. Nothing is
// left behind.
void CheckWritable(const std::string& destination);

}  // namespace bead
