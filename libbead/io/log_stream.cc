#include "libbead/io/log_stream.h"

#include <algorithm>
#include <cmath>

#include "libbead/core/error.h"
#include "libbead/io/hdf5_file.h"
#include "libbead/io/hdf5_rows.h"

namespace bead {

LogStream::LogStream(const std::string& path, std::size_t window)
    : path_(path), window_(std::max<std::size_t>(window, 1)) {
  file_ = std::make_unique<h5::File>(h5::File::OpenRead(path));
  if (!file_->Exists("/log")) throw Error(Located(path, "/log", "the run has no acquisition log"));
  t_ = std::make_unique<h5::RowReader>(*file_, "/log/t_s", std::initializer_list<int>{1}, h5::Kind::kFloat,
                                       H5T_NATIVE_DOUBLE);
  encoder_ = std::make_unique<h5::RowReader>(*file_, "/log/encoder", std::initializer_list<int>{1}, h5::Kind::kInteger,
                                             H5T_NATIVE_INT64);
  rpm_ = std::make_unique<h5::RowReader>(*file_, "/log/screw_rpm", std::initializer_list<int>{1}, h5::Kind::kFloat,
                                         H5T_NATIVE_DOUBLE);
  size_ = t_->rows();
  for (const auto& [reader, name] :
       {std::pair{encoder_.get(), "/log/encoder"}, std::pair{rpm_.get(), "/log/screw_rpm"}})
    if (reader->rows() != size_)
      throw Error(Located(path, name,
                          "holds " + std::to_string(reader->rows()) + " samples, /log/t_s " + std::to_string(size_)));
}

LogStream::~LogStream() = default;

std::unique_ptr<LogStream> LogStream::OpenIfPresent(const std::string& path, std::size_t window) {
  if (!h5::File::OpenRead(path).Exists("/log")) return nullptr;
  return std::make_unique<LogStream>(path, window);
}

void LogStream::Rewind() { next_ = 0; }

bool LogStream::Next(LogWindow& w, bool with_rpm) {
  if (next_ >= size_) return false;
  const std::size_t count = std::min(window_, size_ - next_);
  w.first = next_;
  w.t_s.resize(count), w.encoder.resize(count), w.screw_rpm.resize(with_rpm ? count : 0);
  t_->Read(next_, count, w.t_s.data(), nullptr);
  encoder_->Read(next_, count, w.encoder.data(), nullptr);
  if (with_rpm) rpm_->Read(next_, count, w.screw_rpm.data(), nullptr);
  for (std::size_t i = 0; i < count; ++i) {
    const double t = w.t_s[i];
    auto at = [&]() { return "/log/t_s[" + std::to_string(next_ + i) + "]"; };
    if (!std::isfinite(t)) throw Error(Located(path_, at(), "time is not finite"));
    if (next_ + i > 0 && !(t > previous_t_))
      throw Error(
          Located(path_, at(),
                  "time does not increase (" + std::to_string(previous_t_) + " then " + std::to_string(t) + " s)"));
    previous_t_ = t;
  }
  next_ += count;
  return true;
}

}  // namespace bead
