// ProfileBlockBuilder: collects the points of profiles given one point at
// a time (the points of one profile together), then pads them with NaN into
// a ProfileBlock. Shared by the spec's CSV forms and the imports of other
// tools' files (CSV, .mat, PLY/PCD).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "libbead/io/csv_reader.h"
#include "libbead/io/run_archive.h"

namespace bead {

class ProfileBlockBuilder {
 public:
  // Adds the point (x, z) of profile `id` read from the current row of
  // `csv` (which names the line in errors): a profile's rows must be
  // together and agree on t_s and encoder.
  void Add(const CsvReader& csv, int64_t id, double t_s, int64_t encoder, float x_mm, float z_mm);
  // The same for points from elsewhere: errors name `file` and `where`.
  void Add(const std::string& file, const std::string& where, int64_t id, double t_s, int64_t encoder, float x_mm,
           float z_mm);

  bool empty() const { return profiles_.empty(); }
  std::size_t size() const { return profiles_.size(); }

  // The block (x shared when every profile has the same x); validated,
  // with `file` and `where` naming it in errors.
  ProfileBlock Build(const std::string& file, const std::string& where) const;

 private:
  // Adds the point; the reason when it cannot be added, else empty.
  std::string Append(const char* noun, int64_t id, double t_s, int64_t encoder, float x_mm, float z_mm);
  struct Profile {
    double t;
    int64_t encoder;
    std::vector<float> x, z;
  };
  std::vector<Profile> profiles_;
  std::map<int64_t, bool> seen_;
  int64_t current_id_ = 0;
};

}  // namespace bead
