// RowReader: whole rows [begin, begin + count) of a 1-D or 2-D HDF5
// dataset, read window by window so an archive of any length is read in
// bounded memory.
//
// Where the dataset is float32 little-endian, chunked in whole rows and
// compressed only with HDF5's shuffle and deflate filters (what libbead
// and h5py with compression="gzip", shuffle=True write), the chunks are
// read raw (H5Dread_chunk, on the calling thread: libhdf5 is not
// thread-safe), then inflated (libdeflate, 1.7x zlib's speed on these
// chunks; zlib words the error on a chunk libdeflate refuses) and
// unshuffled on the worker pool. Anything else (other filters or types,
// contiguous storage, a chunk never written) goes through HDF5's own
// H5Dread of the rows, which converts.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "libbead/core/worker_pool.h"
#include "libbead/io/hdf5_file.h"

struct libdeflate_decompressor;

namespace bead::h5 {

class RowReader {
 public:
  // Opens and checks `dataset` (kind, rank among `ranks`, stored size).
  // mem_type: the native type rows are read as (H5T_NATIVE_FLOAT, ...).
  RowReader(const File& file, const std::string& dataset, std::initializer_list<int> ranks, Kind kind, hid_t mem_type);

  const std::vector<hsize_t>& dims() const { return dims_; }
  std::size_t rows() const { return dims_.empty() ? 0 : dims_[0]; }
  std::size_t row_length() const { return row_length_; }
  // Rows per stored chunk (0: not chunked); windows aligned to it read
  // each chunk once.
  std::size_t chunk_rows() const { return chunk_rows_; }
  bool direct() const { return direct_; }

  // Reads rows [begin, begin + count) into `out` (count * row_length()
  // values of the memory type). `pool` may be null (one thread).
  void Read(std::size_t begin, std::size_t count, void* out, WorkerPool* pool);
  // Reads the rows `rows` (increasing) into `out`, one after another: each
  // stored chunk read and decompressed once however many of them it holds.
  void ReadRows(const std::vector<std::size_t>& rows, void* out, WorkerPool* pool);

 private:
  void CheckChunkSize(const std::vector<hsize_t>& chunk, std::size_t type_size) const;
  void ReadThroughHdf5(std::size_t begin, std::size_t count, void* out) const;
  // Reads the stored chunks (by index along the rows) raw into raw_;
  // false when one was never written (or looks odd): then HDF5 reads.
  bool ReadRaw(const std::vector<std::size_t>& chunks);
  // A worker's buffers (each filter step writes the other) and inflater.
  struct Scratch {
    std::array<std::vector<uint8_t>, 2> buffers;
    std::unique_ptr<libdeflate_decompressor, void (*)(libdeflate_decompressor*)> inflater{nullptr, nullptr};
  };
  // Undoes chunk k's filters; returns its rows (in `scratch`'s buffers).
  const uint8_t* Decode(std::size_t k, Scratch& scratch) const;
  // Decodes every chunk in raw_ on the pool; use(k, values) gets each.
  void DecodeEach(const std::function<void(std::size_t, const uint8_t*)>& use, WorkerPool* pool);

  const File* file_;
  std::string name_;
  Handle ds_;
  hid_t mem_type_;
  std::size_t mem_size_;
  std::vector<hsize_t> dims_;
  std::size_t row_length_ = 1;
  std::size_t chunk_rows_ = 0;
  bool direct_ = false;
  std::vector<int> filters_;  // H5Z filter ids in pipeline order
  // Raw chunks of the window being read, and each worker's scratch.
  std::vector<std::vector<uint8_t>> raw_;
  std::vector<uint32_t> masks_;
  std::vector<std::size_t> raw_first_row_;
  std::vector<Scratch> scratch_;
};

}  // namespace bead::h5
