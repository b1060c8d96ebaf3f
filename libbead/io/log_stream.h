// LogStream: a run archive's acquisition log (/log/t_s, encoder,
// screw_rpm) read window by window, so that an hour's log (70 MB at
// 500 Hz) is never held whole; walked again from the start with Rewind.
// Each window is checked as the whole log is (time finite and increasing,
// across window edges too); errors name the file and the sample.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace bead {

namespace h5 {
class File;
class RowReader;
}  // namespace h5

struct LogWindow {
  std::size_t first = 0;  // the log index of t_s[0]
  std::vector<double> t_s;
  std::vector<int64_t> encoder;
  std::vector<double> screw_rpm;
  std::size_t size() const { return t_s.size(); }
};

class LogStream {
 public:
  // Throws, naming the file, when /log is missing or its lengths differ.
  explicit LogStream(const std::string& path, std::size_t window = 65536);
  // Null when the archive has no /log.
  static std::unique_ptr<LogStream> OpenIfPresent(const std::string& path, std::size_t window = 65536);
  ~LogStream();
  LogStream(const LogStream&) = delete;
  LogStream& operator=(const LogStream&) = delete;

  std::size_t size() const { return size_; }
  // The next window into `w`; false at the end. Without `with_rpm`,
  // w.screw_rpm is left empty (a walk that needs only time and encoder
  // decompresses a third less).
  bool Next(LogWindow& w, bool with_rpm = true);
  void Rewind();

 private:
  std::string path_;
  std::size_t window_, size_ = 0, next_ = 0;
  double previous_t_ = 0.0;
  std::unique_ptr<h5::File> file_;
  std::unique_ptr<h5::RowReader> t_, encoder_, rpm_;
};

}  // namespace bead
