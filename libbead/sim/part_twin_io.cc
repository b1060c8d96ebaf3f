#include "libbead/sim/part_twin_io.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

#include "libbead/io/atomic_file.h"
#include "libbead/io/csv_reader.h"
#include "libbead/io/rig_yaml.h"
#include "libbead/io/run_archive.h"
#include "libbead/io/yaml_text.h"
#include "libbead/sim/sim_yaml_reader.h"

namespace bead::sim {
namespace {

void ParsePart(const YAML::Node& root, const Reader& r, PartTwinConfig& c) {
  const YAML::Node p = r.Section(root, "part",
                                 {"shape",
                                  "layers",
                                  "length_mm",
                                  "head_speed_mm_s",
                                  "return_s",
                                  "alternate",
                                  "profile_spacing_mm",
                                  "trail_mm",
                                  "width_mm",
                                  "aspect",
                                  "exponent",
                                  "area_mm2",
                                  "area_wave_mm2",
                                  "wave_period_mm",
                                  "wander_sigma_mm",
                                  "pass_shift_sigma_mm",
                                  "standoff_mm",
                                  "noise_mm",
                                  "shadow_mm",
                                  "point_spacing_mm",
                                  "field_half_mm",
                                  "log_rate_hz",
                                  "displacement_mm3_per_rev",
                                  "bed_radius_mm",
                                  "roads",
                                  "road_spacing_mm",
                                  "contour_length_mm",
                                  "contour_width_mm",
                                  "corner_radius_mm",
                                  "lateral_accel_mm_s2",
                                  "tangential_accel_mm_s2"});
  const std::string at = "part.";
  if (p["shape"].IsDefined()) {
    const std::string shape = r.Text(p["shape"], "part.shape");
    if (shape != "wall" && shape != "contour")
      r.Fail(p["shape"], "part.shape", "is '" + shape + "': the twin prints a wall or a contour");
    if (shape == "contour") c.shape = PartTwinConfig::Shape::kContour;
  }
  r.Get(p, at, "contour_length_mm", c.contour_length_mm, 1.0, 1e5);
  r.Get(p, at, "contour_width_mm", c.contour_width_mm, 1.0, 1e5);
  r.Get(p, at, "corner_radius_mm", c.corner_radius_mm, 0.1, 1e4);
  r.Get(p, at, "lateral_accel_mm_s2", c.lateral_accel_mm_s2, 1e-3, 1e6);
  r.Get(p, at, "tangential_accel_mm_s2", c.tangential_accel_mm_s2, 1e-3, 1e6);
  if (2.0 * c.corner_radius_mm > std::min(c.contour_length_mm, c.contour_width_mm))
    r.Fail(p["corner_radius_mm"], at + "corner_radius_mm", "must be at most half the contour's shorter side");
  r.GetInt(p, at, "layers", c.layers, 1, 200);
  r.Get(p, at, "length_mm", c.length_mm, 1.0, 1e5);
  r.Get(p, at, "head_speed_mm_s", c.head_speed_mm_s, 0.1, 1e4);
  r.Get(p, at, "return_s", c.return_s, 0.0, 1e4);
  r.GetBool(p, at, "alternate", c.alternate);
  r.Get(p, at, "profile_spacing_mm", c.profile_spacing_mm, 0.01, 100.0);
  r.Get(p, at, "trail_mm", c.trail_mm, 0.0, 1e3);
  r.Get(p, at, "width_mm", c.width_mm, 0.1, 100.0);
  r.Get(p, at, "aspect", c.aspect, 0.05, 5.0);
  r.Get(p, at, "exponent", c.exponent, 1.2, 8.0);
  r.Get(p, at, "area_mm2", c.area_mm2, 0.01, 1e4);
  r.Get(p, at, "area_wave_mm2", c.area_wave_mm2, 0.0, 1e4);
  r.Get(p, at, "wave_period_mm", c.wave_period_mm, 0.1, 1e6);
  r.Get(p, at, "wander_sigma_mm", c.wander_sigma_mm, 0.0, 10.0);
  r.Get(p, at, "pass_shift_sigma_mm", c.pass_shift_sigma_mm, 0.0, 10.0);
  r.Get(p, at, "standoff_mm", c.standoff_mm, 0.0, 1e3);
  r.Get(p, at, "noise_mm", c.noise_mm, 0.0, 1.0);
  r.Get(p, at, "shadow_mm", c.shadow_mm, 0.0, 10.0);
  r.Get(p, at, "point_spacing_mm", c.point_spacing_mm, 0.001, 10.0);
  r.Get(p, at, "field_half_mm", c.field_half_mm, 1.0, 1e3);
  r.Get(p, at, "log_rate_hz", c.log_rate_hz, 1.0, 1e5);
  r.Get(p, at, "displacement_mm3_per_rev", c.displacement_mm3_per_rev, 1e-3, 1e9);
  r.Get(p, at, "bed_radius_mm", c.bed_radius_mm, 0.0, 1e5);
  r.GetInt(p, at, "roads", c.roads, 1, 50);
  if (c.alternate && (c.shape != PartTwinConfig::Shape::kWall || c.roads > 1))
    r.Fail(p["alternate"], at + "alternate", "lays a straight wall back and forth: shape wall, roads 1");
  r.Get(p, at, "road_spacing_mm", c.road_spacing_mm, 0.01, 1e3);
  if (c.roads > 1 && (c.layers != 1 || c.bed_radius_mm > 0))
    r.Fail(p["roads"], at + "roads", "above 1 is one layer of roads on a flat bed: set layers: 1 and no bed_radius_mm");
  const double span = 0.5 * (c.roads - 1) * c.road_spacing_mm, bare = ReferenceWidthMm(c);
  if (c.roads > 1 && c.field_half_mm <= span + 0.5 * c.width_mm + bare)
    r.Fail(p["field_half_mm"], at + "field_half_mm",
           "must leave the reference areas' bare bed (5 mm, or a quarter of field_half_mm if less) beside the outer "
           "roads: more than (roads - 1) spacing / 2 + width / 2 + that");
  if (c.bed_radius_mm > 0 && c.bed_radius_mm <= c.field_half_mm)
    r.Fail(p["bed_radius_mm"], at + "bed_radius_mm", "must exceed field_half_mm: the pipe spans the profile");
  if (c.area_wave_mm2 >= c.area_mm2) r.Fail(p["area_wave_mm2"], at + "area_wave_mm2", "must be less than area_mm2");
  // A bead sunk into the surface below holds at most its whole outline:
  // 4 a b Gamma(1 + 1/p)^2 / Gamma(1 + 2/p) (pi a b for the ellipse).
  const double a = 0.5 * c.width_mm, b = c.aspect * a, p_ = c.exponent;
  const double whole = 4.0 * a * b * std::pow(std::tgamma(1.0 + 1.0 / p_), 2) / std::tgamma(1.0 + 2.0 / p_);
  if (c.roads <= 1 && c.area_mm2 + c.area_wave_mm2 >= whole) {
    std::ostringstream what;
    what << std::setprecision(4) << "with area_wave_mm2 asks up to " << c.area_mm2 + c.area_wave_mm2
         << " mm^2 of a bead whose whole outline (width_mm, aspect, exponent) holds " << whole
         << " mm^2: it would float off the surface below; lower the area or widen the bead";
    r.Fail(p["area_mm2"], at + "area_mm2", what.str());
  }
  if (c.field_half_mm <= 0.5 * c.width_mm + bare)
    r.Fail(p["field_half_mm"], at + "field_half_mm",
           "must leave the reference areas' bare bed (5 mm, or a quarter of field_half_mm if less) beside the bead: "
           "more than width / 2 + that");
}

void WriteTruth(const std::string& path, const std::vector<PartTruthRow>& rows) {
  AtomicFile out(path);
  out.stream() << "layer,path_mm,area_mm2,visible_area_mm2,height_mm,width_mm,center_x_mm,offset_below_mm,"
                  "pass_shift_mm\n";
  for (const PartTruthRow& t : rows)
    out.stream() << t.layer << ',' << CsvNumber(t.path_mm) << ',' << CsvNumber(t.area_mm2) << ','
                 << CsvNumber(t.visible_area_mm2) << ',' << CsvNumber(t.height_mm) << ',' << CsvNumber(t.width_mm)
                 << ',' << CsvNumber(t.center_x_mm) << ',' << CsvNumber(t.offset_below_mm) << ','
                 << CsvNumber(t.pass_shift_mm) << '\n';
  out.Commit();
}

void WriteRoadTruth(const std::string& path, const std::vector<PartRoadTruth>& rows) {
  AtomicFile out(path);
  out.stream() << "profile,bead,area_mm2,center_x_mm,width_mm,height_mm,naive_area_mm2\n";
  for (const PartRoadTruth& t : rows)
    out.stream() << t.profile << ',' << t.road << ',' << CsvNumber(t.area_mm2) << ',' << CsvNumber(t.center_x_mm) << ','
                 << CsvNumber(t.width_mm) << ',' << CsvNumber(t.height_mm) << ',' << CsvNumber(t.naive_area_mm2)
                 << '\n';
  out.Commit();
}

}  // namespace

std::optional<PartTwinConfig> ReadPartTwinConfig(const std::string& path) {
  const YAML::Node root = ParseYamlText(ReadTextFile(path, "simulation config"), path);
  if (!root.IsMap() || !root["part"].IsDefined()) return std::nullopt;
  const Reader r(path);
  for (const auto& kv : root) {
    const std::string k = r.Text(kv.first, "<key>");
    if (k != "part" && k != "seed" && k != "name")
      r.Fail(kv.first, k, "a part twin's config holds part: and seed only");
  }
  PartTwinConfig c;
  r.GetInt(root, "", "seed", c.seed, 0, 1e15);
  ParsePart(root, r, c);
  return c;
}

void WritePartTwin(const std::string& folder, const PartTwin& twin) {
  std::filesystem::create_directories(folder);
  WriteRunArchive(folder + "/part.h5", twin.scan);
  WriteRigFile(folder + "/rig.yaml", MakeRigFile(twin.rig));
  WriteTruth(folder + "/truth.csv", twin.truth);
  if (!twin.road_truth.empty()) WriteRoadTruth(folder + "/truth_roads.csv", twin.road_truth);
}

}  // namespace bead::sim
