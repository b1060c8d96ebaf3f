#include "libbead/io/profile_stream.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "libbead/core/error.h"
#include "libbead/io/hdf5_file.h"
#include "libbead/io/hdf5_rows.h"
#include "libbead/io/run_archive.h"

namespace bead {
namespace {

template <typename T>
void Take(std::vector<T>& to, const std::vector<T>& from, std::size_t begin, std::size_t count) {
  to.resize(count);
  if (count) std::memcpy(to.data(), from.data() + begin, count * sizeof(T));
}

}  // namespace

ProfileStream::ProfileStream(const std::string& path, WorkerPool& pool)
    : name_(path), file_(std::make_unique<h5::File>(h5::File::OpenRead(path))), pool_(&pool) {
  const h5::File& f = *file_;
  t_ = std::make_unique<h5::RowReader>(f, "/profiles/t_s", std::initializer_list<int>{1}, h5::Kind::kFloat,
                                       H5T_NATIVE_DOUBLE);
  // A part scan (format 1.1) has no wheel and no encoder: 0 for each profile.
  const auto root = f.ReadStringAttributes("/");
  const auto kind = root.find("kind");
  const bool part = kind != root.end() && kind->second == "part" && !f.Exists("/profiles/encoder");
  if (!part)
    encoder_ = std::make_unique<h5::RowReader>(f, "/profiles/encoder", std::initializer_list<int>{1},
                                               h5::Kind::kInteger, H5T_NATIVE_INT64);
  z_ = std::make_unique<h5::RowReader>(f, "/profiles/z_mm", std::initializer_list<int>{2}, h5::Kind::kFloat,
                                       H5T_NATIVE_FLOAT);
  x_ = std::make_unique<h5::RowReader>(f, "/profiles/x_mm", std::initializer_list<int>{1, 2}, h5::Kind::kFloat,
                                       H5T_NATIVE_FLOAT);
  size_ = t_->rows();
  points_ = z_->row_length();
  CheckProfileShapes(path, "/profiles", size_, encoder_ ? encoder_->rows() : size_,
                     {z_->dims().begin(), z_->dims().end()}, {x_->dims().begin(), x_->dims().end()});
  shared_x_ = x_->dims().size() == 1;
  if (shared_x_) {
    x_shared_.resize(points_);
    x_->Read(0, points_, x_shared_.data(), nullptr);
    x_.reset();
  }
}

ProfileStream::ProfileStream(std::string name, ProfileBlock block) : name_(std::move(name)) {
  size_ = block.size();
  points_ = block.points;
  shared_x_ = block.shared_x;
  memory_ = std::move(block);
}

ProfileStream::~ProfileStream() = default;

std::size_t ProfileStream::WindowRows(std::size_t target) const {
  const std::size_t chunk = z_ && z_->chunk_rows() ? z_->chunk_rows() : 1;
  return std::max<std::size_t>(1, (target + chunk - 1) / chunk) * chunk;
}

void ProfileStream::Read(std::size_t begin, std::size_t count, ProfileBlock& b) {
  if (begin > size_ || count > size_ - begin)
    throw Error(Located(name_, "/profiles",
                        "internal: profiles " + std::to_string(begin) + "+" + std::to_string(count) + " beyond " +
                            std::to_string(size_)));
  b.points = points_;
  b.shared_x = shared_x_;
  if (memory_) {
    const ProfileBlock& m = *memory_;
    Take(b.t_s, m.t_s, begin, count);
    Take(b.encoder, m.encoder, begin, count);
    if (shared_x_)
      b.x_mm = m.x_mm;
    else
      Take(b.x_mm, m.x_mm, begin * points_, count * points_);
    Take(b.z_mm, m.z_mm, begin * points_, count * points_);
  } else {
    b.t_s.resize(count);
    b.encoder.resize(count);
    b.z_mm.resize(count * points_);
    t_->Read(begin, count, b.t_s.data(), nullptr);
    if (encoder_)
      encoder_->Read(begin, count, b.encoder.data(), nullptr);
    else
      std::fill(b.encoder.begin(), b.encoder.end(), 0);
    if (shared_x_) {
      if (b.x_mm.size() != points_) b.x_mm = x_shared_;
    } else {
      b.x_mm.resize(count * points_);
      x_->Read(begin, count, b.x_mm.data(), pool_);
    }
    z_->Read(begin, count, b.z_mm.data(), pool_);
  }
  const double previous = begin > 0 && begin == next_ ? last_t_ : std::nan("");
  ValidateProfileRows(b, begin, previous, name_, "/profiles");
  next_ = begin + count;
  if (count) last_t_ = b.t_s.back();
}

const ProfileBlock* ProfileStream::InMemory() {
  if (!memory_) return nullptr;
  if (!memory_checked_) ValidateProfileRows(*memory_, 0, std::nan(""), name_, "/profiles");
  memory_checked_ = true;
  return &*memory_;
}

void ProfileStream::ReadRows(const std::vector<std::size_t>& rows, ProfileBlock& b) {
  for (std::size_t r : rows)
    if (r >= size_)
      throw Error(
          Located(name_, "/profiles", "internal: profile " + std::to_string(r) + " beyond " + std::to_string(size_)));
  const std::size_t n = rows.size();
  b.points = points_;
  b.shared_x = shared_x_;
  b.t_s.resize(n);
  b.encoder.resize(n);
  b.z_mm.resize(n * points_);
  if (!shared_x_) b.x_mm.resize(n * points_);
  if (memory_) {
    const ProfileBlock& m = *memory_;
    if (shared_x_) b.x_mm = m.x_mm;
    for (std::size_t j = 0; j < n; ++j) {
      b.t_s[j] = m.t_s[rows[j]];
      b.encoder[j] = m.encoder[rows[j]];
      std::memcpy(b.z_mm.data() + j * points_, m.z_mm.data() + rows[j] * points_, points_ * sizeof(float));
      if (!shared_x_)
        std::memcpy(b.x_mm.data() + j * points_, m.x_mm.data() + rows[j] * points_, points_ * sizeof(float));
    }
    return;
  }
  t_->ReadRows(rows, b.t_s.data(), nullptr);
  if (encoder_)
    encoder_->ReadRows(rows, b.encoder.data(), nullptr);
  else
    std::fill(b.encoder.begin(), b.encoder.end(), 0);
  if (shared_x_)
    b.x_mm = x_shared_;
  else
    x_->ReadRows(rows, b.x_mm.data(), pool_);
  z_->ReadRows(rows, b.z_mm.data(), pool_);
}

}  // namespace bead
