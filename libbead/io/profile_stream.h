// ProfileStream: a run's profiles window by window, so that an archive of
// any length is processed in bounded memory. From a run archive the rows
// are read as they are needed (hdf5_rows.h: chunks inflated on the worker
// pool); from a profiles CSV (which has no index to seek in) the whole
// block is read once and windows are copied out of it.
//
// Every window is checked as ValidateProfileBlock checks a whole block
// (lengths, finite increasing time across windows too, no infinite
// coordinate); errors name the file, the dataset and the row.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "libbead/core/run_data.h"
#include "libbead/core/worker_pool.h"

namespace bead {

namespace h5 {
class File;
class RowReader;
}  // namespace h5

class ProfileStream {
 public:
  // A run archive's /profiles; `pool` decompresses (it must outlive the stream).
  ProfileStream(const std::string& path, WorkerPool& pool);
  // Profiles already in memory (a profiles CSV).
  ProfileStream(std::string name, ProfileBlock block);
  ~ProfileStream();
  ProfileStream(const ProfileStream&) = delete;
  ProfileStream& operator=(const ProfileStream&) = delete;

  const std::string& name() const { return name_; }
  std::size_t size() const { return size_; }
  std::size_t points() const { return points_; }
  // Rows per window: whole stored chunks, about `target` rows.
  std::size_t WindowRows(std::size_t target = 4096) const;

  // Profiles [begin, begin + count) into `block` (its buffers reused: no
  // allocation once they are large enough, and none zero-filled).
  void Read(std::size_t begin, std::size_t count, ProfileBlock& block);
  // Profiles already in memory: all of them, checked once as Read checks a
  // window (no copy: a pass reads their views in place); nullptr for an
  // archive, which is read window by window.
  const ProfileBlock* InMemory();
  // The profiles `rows` (increasing) into `block`, in that order: each
  // stored chunk decompressed once (the pooled occlusion's few dozen
  // profiles). Not checked again: they are rows a pass of Read has seen.
  void ReadRows(const std::vector<std::size_t>& rows, ProfileBlock& block);

 private:
  std::string name_;
  std::size_t size_ = 0, points_ = 0;
  bool shared_x_ = true;
  std::vector<float> x_shared_;
  std::unique_ptr<h5::File> file_;
  std::unique_ptr<h5::RowReader> t_, encoder_, x_, z_;
  WorkerPool* pool_ = nullptr;
  std::optional<ProfileBlock> memory_;
  bool memory_checked_ = false;
  std::size_t next_ = 0;  // the row after the last window read ...
  double last_t_ = 0;     // ... and its time, for the check across windows
};

}  // namespace bead
