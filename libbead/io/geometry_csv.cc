#include "libbead/io/geometry_csv.h"

#include "libbead/io/atomic_file.h"
#include "libbead/io/csv_reader.h"

namespace bead {

void WriteGeometryCsv(const std::string& path, const std::vector<GeometryRow>& rows) {
  AtomicFile out(path);
  auto& s = out.stream();
  s << "profile,t_s,encoder,area_mm2,width_mm,height_mm,area_corrected_mm2,valid,"
       "center_x_mm,reference_rms_mm,reference_points,threshold_mm,dropped_points,status,"
       "area_sigma_mm2,occlusion_bias_mm2,area_corrected_sigma_mm2\n";
  for (const GeometryRow& r : rows) {
    const BeadGeometry& g = r.geometry;
    const bool ok = g.valid();
    auto value = [ok](double v) { return ok ? CsvNumber(v) : std::string(); };
    s << r.profile << ',' << CsvNumber(r.t_s) << ',' << r.encoder << ',' << value(g.area_mm2) << ','
      << value(g.width_mm) << ',' << value(g.height_mm) << ',' << value(r.area_corrected_mm2) << ','
      << (ok ? 1 : 0) << ',' << value(g.center_x_mm) << ',' << CsvNumber(g.reference.residual_rms_mm) << ','
      << g.reference.points_used << ',' << CsvNumber(g.threshold_mm) << ',' << g.dropped_points << ','
      << StatusName(g.status) << ',' << value(g.area_sigma_mm2) << ',' << value(r.occlusion_bias_mm2) << ','
      << value(r.area_corrected_sigma_mm2) << '\n';
  }
  out.Commit();
}

}  // namespace bead
