#include "libbead/io/geometry_csv.h"

#include <charconv>
#include <type_traits>

#include "libbead/io/csv_reader.h"

namespace bead {

GeometryCsvWriter::GeometryCsvWriter(const std::string& path) : out_(path) {
  out_.stream() << "profile,t_s,encoder,area_mm2,width_mm,height_mm,area_corrected_mm2,valid,"
                   "center_x_mm,reference_rms_mm,reference_points,threshold_mm,dropped_points,status,"
                   "area_sigma_mm2,occlusion_bias_mm2,area_corrected_sigma_mm2\n";
}

void GeometryCsvWriter::Append(const GeometryRow& r) {
  const BeadGeometry& g = r.geometry;
  const bool ok = g.valid();
  std::string& s = line_;
  s.clear();
  auto add = [&s](const char* v) {
    s += v;
    s += ',';
  };
  // Shortest round-trip text for doubles (empty for NaN), whole numbers as they are.
  auto number = [&s](auto v) {
    if constexpr (std::is_floating_point_v<decltype(v)>) {
      AppendCsvNumber(s, v);
    } else {
      char buf[24];
      const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);
      if (ec == std::errc()) s.append(buf, end);
    }
    s += ',';
  };
  auto value = [&](double v) { ok ? number(v) : void(s += ','); };
  number(r.profile);
  number(r.t_s);
  number(r.encoder);
  value(g.area_mm2);
  value(g.width_mm);
  value(g.height_mm);
  value(r.area_corrected_mm2);
  add(ok ? "1" : "0");
  value(g.center_x_mm);
  number(g.reference.residual_rms_mm);
  number(g.reference.points_used);
  number(g.threshold_mm);
  number(g.dropped_points);
  add(StatusName(g.status));
  value(g.area_sigma_mm2);
  value(r.occlusion_bias_mm2);
  value(r.area_corrected_sigma_mm2);
  s.back() = '\n';
  out_.stream() << s;
}

void GeometryCsvWriter::Commit() { out_.Commit(); }

void WriteGeometryCsv(const std::string& path, const std::vector<GeometryRow>& rows) {
  GeometryCsvWriter out(path);
  for (const GeometryRow& r : rows) out.Append(r);
  out.Commit();
}

}  // namespace bead
