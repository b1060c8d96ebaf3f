#include "libbead/io/vendor_csv.h"

#include <cmath>
#include <filesystem>
#include <vector>

#include "libbead/core/error.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/profile_block_builder.h"

namespace bead {
namespace {

// The index of the column named `name` in `header`, naming the columns
// there are when it is missing or not unique.
std::size_t ColumnIndex(const CsvReader& csv, const std::vector<std::string>& header, const std::string& name,
                        const char* role) {
  std::size_t found = header.size(), count = 0;
  for (std::size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) found = i, ++count;
  if (count == 1) return found;
  std::string all;
  for (const auto& h : header) all += (all.empty() ? "" : ", ") + h;
  csv.Fail(std::string(count == 0 ? "no column '" : "more than one column '") + name + "' for the " + role +
           " (the header has: " + all + ")");
}

// A part scan's profile: its layer, place and frame, from its first row.
void AddPlace(CsvReader& csv, const ImportColumns& c, std::size_t i_layer, std::size_t i_path, std::size_t i_fz,
              std::size_t i_fx, PartPlaces& places) {
  places.layer.push_back(csv.Int64(i_layer, c.layer.c_str()));
  places.path_mm.push_back(c.path.empty() ? 0.0 : csv.Double(i_path, c.path.c_str()));
  places.frame_z_mm.push_back(c.frame_z.empty() ? 0.0 : csv.Double(i_fz, c.frame_z.c_str()));
  places.frame_x_mm.push_back(c.frame_x.empty() ? 0.0 : csv.Double(i_fx, c.frame_x.c_str()));
}

// Without a path column: each profile placed at the head's speed times its
// time since its layer's first profile.
void PlaceAtHeadSpeed(const std::vector<double>& t, double speed, PartPlaces& places) {
  double start = 0.0;
  for (std::size_t i = 0; i < t.size() && i < places.size(); ++i) {
    if (i == 0 || places.layer[i] != places.layer[i - 1]) start = t[i];
    places.path_mm[i] = speed * (t[i] - start);
  }
}

}  // namespace

ImportedRun ReadVendorCsv(const std::string& path, const ImportColumns& c) {
  CheckImportColumns(path, c, true);
  CsvReader csv(path);
  const std::vector<std::string> header = csv.Header({}, "vendor CSV");
  const std::size_t i_profile = ColumnIndex(csv, header, c.profile, "profile id");
  const std::size_t i_time = ColumnIndex(csv, header, c.time, "time");
  const std::size_t i_x = ColumnIndex(csv, header, c.x, "x");
  const std::size_t i_z = ColumnIndex(csv, header, c.z, "z");
  const bool has_encoder = !c.encoder.empty();
  const std::size_t i_encoder = has_encoder ? ColumnIndex(csv, header, c.encoder, "encoder") : 0;
  const float sign = c.z_is_distance ? -1.0f : 1.0f;
  auto optional_column = [&](const std::string& name, const char* what) {
    return name.empty() ? header.size() : ColumnIndex(csv, header, name, what);
  };
  const std::size_t i_layer = optional_column(c.layer, "layer"), i_path = optional_column(c.path, "path");
  const std::size_t i_fz = optional_column(c.frame_z, "frame z"), i_fx = optional_column(c.frame_x, "frame x");

  ImportedRun result;
  ProfileBlockBuilder builder;
  PartPlaces places;
  int64_t current = 0;
  double current_t = 0.0;
  while (csv.Next()) {
    const int64_t id = csv.Int64(i_profile, c.profile.c_str());
    if (builder.empty() || id != current) {
      current = id;
      current_t = csv.Double(i_time, c.time.c_str()) * c.time_scale;
      if (c.part()) AddPlace(csv, c, i_layer, i_path, i_fz, i_fx, places);
    }
    const int64_t encoder = has_encoder ? csv.Int64(i_encoder, c.encoder.c_str()) : 0;
    builder.Add(csv, id, current_t, encoder, csv.Coordinate(i_x, c.x.c_str()), sign * csv.Coordinate(i_z, c.z.c_str()));
    ++result.rows;
  }
  if (builder.empty()) throw Error(Located(path, "", "holds no point rows"));
  result.run.profiles = builder.Build(path, "profiles");
  result.run.attributes["imported_from"] = std::filesystem::path(path).filename().string();
  if (!has_encoder) result.run.attributes[kEncoderAttribute] = kEncoderAbsent;
  if (c.part()) {
    if (c.path.empty()) PlaceAtHeadSpeed(result.run.profiles.t_s, c.head_speed_mm_s, places);
    ValidatePartPlaces(places, result.run.profiles.size(), path, "profiles");
    result.run.part = std::move(places);
  }
  return result;
}

}  // namespace bead
