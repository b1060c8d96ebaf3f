#include "libbead/io/hdf5_rows.h"

#include <libdeflate.h>
#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <functional>

#include "libbead/core/error.h"

namespace bead::h5 {

RowReader::RowReader(const File& file, const std::string& dataset, std::initializer_list<int> ranks, Kind kind,
                     hid_t mem_type)
    : file_(&file), name_(dataset), mem_type_(mem_type), mem_size_(H5Tget_size(mem_type)) {
  ds_ = file.OpenDataset(dataset, ranks, kind, dims_);
  for (std::size_t d = 1; d < dims_.size(); ++d) row_length_ *= dims_[d];
  Handle dcpl(H5Dget_create_plist(ds_.get()), H5Pclose);
  Handle type(H5Dget_type(ds_.get()), H5Tclose);
  if (!dcpl.valid() || H5Pget_layout(dcpl.get()) != H5D_CHUNKED) return;
  std::vector<hsize_t> chunk(dims_.size());
  if (H5Pget_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()) != static_cast<int>(chunk.size())) return;
  CheckChunkSize(chunk, H5Tget_size(type.get()));
  chunk_rows_ = chunk.empty() ? 0 : chunk[0];
  // Direct reads: float32 LE in and out, chunks of whole rows.
  if (!(H5Tequal(type.get(), H5T_IEEE_F32LE) > 0 && H5Tequal(mem_type, H5T_NATIVE_FLOAT) > 0)) return;
  if (H5Tequal(H5T_NATIVE_FLOAT, H5T_IEEE_F32LE) <= 0) return;
  for (std::size_t d = 1; d < dims_.size(); ++d)
    if (chunk[d] != dims_[d]) return;
  if (chunk_rows_ == 0) return;
  const int n = H5Pget_nfilters(dcpl.get());
  for (int i = 0; i < n; ++i) {
    unsigned flags = 0, config = 0;
    std::size_t nelmts = 0;
    const H5Z_filter_t id =
        H5Pget_filter2(dcpl.get(), static_cast<unsigned>(i), &flags, &nelmts, nullptr, 0, nullptr, &config);
    if (id != H5Z_FILTER_DEFLATE && id != H5Z_FILTER_SHUFFLE) return;
    filters_.push_back(static_cast<int>(id));
  }
  direct_ = true;
}

// A chunk is read and inflated whole (here and inside libhdf5): one far
// beyond the dataset it holds (more than twice its values, and over 64 MB)
// is a damaged header, refused before anything is allocated for it.
void RowReader::CheckChunkSize(const std::vector<hsize_t>& chunk, std::size_t type_size) const {
  double values = 1, declared = 1;
  for (hsize_t c : chunk) values *= static_cast<double>(c);
  for (hsize_t d : dims_) declared *= static_cast<double>(d);
  const double bytes = values * static_cast<double>(type_size);
  if (bytes > 64.0 * 1048576.0 && values > 2 * declared)
    throw Error(Located(file_->name(), name_,
                        "damaged: its chunks declare " + std::to_string(static_cast<long long>(bytes)) +
                            " bytes each for a dataset of " + std::to_string(static_cast<long long>(declared)) +
                            " values"));
}

void RowReader::ReadThroughHdf5(std::size_t begin, std::size_t count, void* out) const {
  Handle space(H5Dget_space(ds_.get()), H5Sclose);
  std::vector<hsize_t> start(dims_.size(), 0), size = dims_;
  start[0] = begin;
  size[0] = count;
  Handle mem(H5Screate_simple(static_cast<int>(size.size()), size.data(), nullptr), H5Sclose);
  if (H5Sselect_hyperslab(space.get(), H5S_SELECT_SET, start.data(), nullptr, size.data(), nullptr) < 0 ||
      H5Dread(ds_.get(), mem_type_, mem.get(), space.get(), H5P_DEFAULT, out) < 0)
    throw Error(Located(
        file_->name(), name_,
        "cannot read rows " + std::to_string(begin) + " to " + std::to_string(begin + count - 1) + " (damaged?)"));
}

namespace {

// Inflates a zlib stream (HDF5's deflate filter) of exactly `bytes` into
// `to`: libdeflate when it takes the stream whole; zlib otherwise, which
// also words the error. Both check the stream's Adler-32.
void Inflate(libdeflate_decompressor* inflater, const uint8_t* data, std::size_t size, uint8_t* to, std::size_t bytes,
             const std::string& file, const std::string& where) {
  std::size_t got = 0;
  if (inflater && libdeflate_zlib_decompress(inflater, data, size, to, bytes, &got) == LIBDEFLATE_SUCCESS &&
      got == bytes)
    return;
  uLongf zgot = bytes;
  const int rc = uncompress(to, &zgot, data, size);
  if (rc != Z_OK || zgot != bytes)
    throw Error(Located(file, where,
                        "damaged compressed data (inflates to " + std::to_string(zgot) + " bytes, a chunk is " +
                            std::to_string(bytes) + ")"));
}

// HDF5's shuffle filter stores byte b of value i at b * values + i; the
// values are float32 little-endian on a little-endian host (the reader is
// direct only then), so a value's bytes assemble into one word. Word by
// word is 2.5x the byte scatter.
void Unshuffle4(const uint8_t* planes, std::size_t values, uint8_t* to) {
  const uint8_t *p0 = planes, *p1 = p0 + values, *p2 = p1 + values, *p3 = p2 + values;
  for (std::size_t i = 0; i < values; ++i) {
    const uint32_t word = uint32_t{p0[i]} | uint32_t{p1[i]} << 8 | uint32_t{p2[i]} << 16 | uint32_t{p3[i]} << 24;
    std::memcpy(to + 4 * i, &word, 4);
  }
}

}  // namespace

// Undoes the filters of chunk k of those read (the last filter first).
// The raw bytes stay as read; each step writes the worker's other scratch
// buffer.
const uint8_t* RowReader::Decode(std::size_t k, Scratch& scratch) const {
  const std::size_t values = chunk_rows_ * row_length_, bytes = values * sizeof(float);
  const std::string where = name_ + " chunk at row " + std::to_string(raw_first_row_[k]);
  const uint8_t* data = raw_[k].data();
  std::size_t size = raw_[k].size();
  int next = 0;  // the scratch buffer the next step writes
  for (std::size_t f = filters_.size(); f-- > 0;) {
    if (masks_[k] & (1u << f)) continue;  // filter skipped for this chunk
    std::vector<uint8_t>& to = scratch.buffers[next];
    to.resize(bytes);
    if (filters_[f] == H5Z_FILTER_DEFLATE) {
      if (!scratch.inflater) scratch.inflater = {libdeflate_alloc_decompressor(), libdeflate_free_decompressor};
      Inflate(scratch.inflater.get(), data, size, to.data(), bytes, file_->name(), where);
    } else {  // shuffle
      if (size != bytes) throw Error(Located(file_->name(), where, "damaged chunk (wrong size)"));
      Unshuffle4(data, values, to.data());
    }
    data = to.data();
    size = bytes;
    next ^= 1;
  }
  if (size != bytes) throw Error(Located(file_->name(), where, "damaged chunk (wrong size)"));
  return data;
}

// Decodes every chunk in raw_ on the pool (or here) and hands each to
// `use` with its decoded values, on the thread that decoded it.
void RowReader::DecodeEach(const std::function<void(std::size_t, const uint8_t*)>& use, WorkerPool* pool) {
  const unsigned workers = pool ? pool->size() : 1;
  if (scratch_.size() < workers) scratch_.resize(workers);
  auto decode = [&](std::size_t k, unsigned worker) { use(k, Decode(k, scratch_[worker])); };
  if (pool)
    pool->Run(raw_.size(), decode);
  else
    for (std::size_t k = 0; k < raw_.size(); ++k) decode(k, 0);
}

bool RowReader::ReadRaw(const std::vector<std::size_t>& chunks) {
  raw_.resize(chunks.size());
  masks_.assign(chunks.size(), 0);
  raw_first_row_.resize(chunks.size());
  std::vector<hsize_t> offset(dims_.size(), 0);
  for (std::size_t k = 0; k < chunks.size(); ++k) {
    offset[0] = chunks[k] * chunk_rows_;
    hsize_t stored = 0;
    if (H5Dget_chunk_storage_size(ds_.get(), offset.data(), &stored) < 0 || stored == 0 ||
        stored > 2 * chunk_rows_ * row_length_ * sizeof(float) + 65536)
      return false;  // never written (fill values), or odd: HDF5 decides
    raw_[k].resize(stored);
    if (H5Dread_chunk(ds_.get(), H5P_DEFAULT, offset.data(), &masks_[k], raw_[k].data()) < 0)
      throw Error(
          Located(file_->name(), name_ + " chunk at row " + std::to_string(offset[0]), "cannot read (damaged?)"));
    raw_first_row_[k] = offset[0];
  }
  return true;
}

void RowReader::Read(std::size_t begin, std::size_t count, void* out, WorkerPool* pool) {
  if (count == 0) return;
  if (begin + count > rows())
    throw Error(Located(file_->name(), name_, "internal: rows beyond the dataset's " + std::to_string(rows())));
  if (!direct_ || row_length_ == 0) return ReadThroughHdf5(begin, count, out);
  std::vector<std::size_t> chunks;
  for (std::size_t c = begin / chunk_rows_; c <= (begin + count - 1) / chunk_rows_; ++c) chunks.push_back(c);
  if (!ReadRaw(chunks)) return ReadThroughHdf5(begin, count, out);
  const std::size_t row_bytes = row_length_ * sizeof(float);
  auto* dest = static_cast<uint8_t*>(out);
  DecodeEach(
      [&](std::size_t k, const uint8_t* data) {  // the chunk's rows within [begin, begin + count)
        const std::size_t first = raw_first_row_[k];
        const std::size_t lo = std::max(first, begin), hi = std::min(first + chunk_rows_, begin + count);
        if (hi > lo)
          std::memcpy(dest + (lo - begin) * row_bytes, data + (lo - first) * row_bytes, (hi - lo) * row_bytes);
      },
      pool);
}

void RowReader::ReadRows(const std::vector<std::size_t>& rows, void* out, WorkerPool* pool) {
  if (rows.empty()) return;
  const std::size_t row_bytes = row_length_ * mem_size_;
  auto* dest = static_cast<uint8_t*>(out);
  // The chunks holding the rows, each once; rows are increasing.
  std::vector<std::size_t> chunks;
  if (direct_ && row_length_ > 0)
    for (std::size_t r : rows)
      if (chunks.empty() || chunks.back() != r / chunk_rows_) chunks.push_back(r / chunk_rows_);
  if (chunks.empty() || !ReadRaw(chunks)) {  // not direct: row by row through HDF5
    for (std::size_t j = 0; j < rows.size(); ++j) ReadThroughHdf5(rows[j], 1, dest + j * row_bytes);
    return;
  }
  DecodeEach(
      [&](std::size_t k, const uint8_t* data) {
        for (std::size_t j = 0; j < rows.size(); ++j)
          if (rows[j] / chunk_rows_ == chunks[k])
            std::memcpy(dest + j * row_bytes, data + (rows[j] - chunks[k] * chunk_rows_) * row_bytes, row_bytes);
      },
      pool);
}

}  // namespace bead::h5
