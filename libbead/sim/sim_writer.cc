#include "libbead/sim/sim_writer.h"

#include <filesystem>

#include "libbead/core/error.h"
#include "libbead/io/atomic_file.h"
#include "libbead/io/hdf5_file.h"
#include "libbead/io/rig_yaml.h"

namespace bead::sim {
namespace {

void WriteTruth(const std::string& path, const Truth& t) {
  AtomicFile out(path);
  {
    h5::File f = h5::File::Create(out.temp_path(), path);
    auto put = [&](const std::string& name, const std::vector<double>& v) { f.Write(name, v, {v.size()}); };
    put("/flow/t_s", t.flow.t_s);
    put("/flow/flow_mm3_s", t.flow.flow_mm3_s);
    put("/flow/area_mm2", t.flow.area_mm2);
    put("/flow/surface_speed_mm_s", t.flow.surface_speed_mm_s);
    put("/flow/screw_rpm", t.flow.screw_rpm);
    const ProfileTruth& p = t.profiles;
    put("/profiles/t_s", p.t_s);
    put("/profiles/t_extruded_s", p.t_extruded_s);
    put("/profiles/area_true_mm2", p.area_true_mm2);
    put("/profiles/area_visible_mm2", p.area_visible_mm2);
    put("/profiles/max_width_mm", p.max_width_mm);
    put("/profiles/contact_width_mm", p.contact_width_mm);
    put("/profiles/height_mm", p.height_mm);
    put("/profiles/center_x_mm", p.center_x_mm);
    f.Write("/profiles/dropped", p.dropped, {p.dropped.size()});
    put("/pins/placement_error_mm", t.pins.placement_error_mm);
    put("/pins/peak_counts", t.pins.peak_counts);
    put("/offset_counts", {t.offset_counts});
    put("/rig_file_offset_counts", {t.rig_file_offset_counts});
    put("/total_volume_mm3", {t.total_volume_mm3});
    f.Flush();
  }
  out.Commit();
}

}  // namespace

void WriteSimulatedRun(const std::string& dir, const SimulatedRun& run) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (!std::filesystem::is_directory(dir)) throw Error(Located(dir, "", "cannot create the output folder"));
  const std::filesystem::path d(dir);
  WriteRunArchive((d / "run.h5").string(), run.run);
  WritePinScanArchive((d / "pins.h5").string(), run.pins);
  WriteRigFile((d / "rig.yaml").string(), MakeRigFile(run.rig_file));
  WriteTruth((d / "truth.h5").string(), run.truth);
}

Truth ReadTruth(const std::string& path) {
  const h5::File f = h5::File::OpenRead(path);
  auto get = [&](const std::string& name) { return f.ReadDouble(name, {1}).data; };
  Truth t;
  t.flow = {get("/flow/t_s"), get("/flow/flow_mm3_s"), get("/flow/area_mm2"), get("/flow/surface_speed_mm_s"),
            get("/flow/screw_rpm")};
  ProfileTruth& p = t.profiles;
  p.t_s = get("/profiles/t_s");
  p.t_extruded_s = get("/profiles/t_extruded_s");
  p.area_true_mm2 = get("/profiles/area_true_mm2");
  p.area_visible_mm2 = get("/profiles/area_visible_mm2");
  p.max_width_mm = get("/profiles/max_width_mm");
  p.contact_width_mm = get("/profiles/contact_width_mm");
  p.height_mm = get("/profiles/height_mm");
  p.center_x_mm = get("/profiles/center_x_mm");
  p.dropped = f.ReadInt64("/profiles/dropped", {1}).data;
  t.pins.placement_error_mm = get("/pins/placement_error_mm");
  t.pins.peak_counts = get("/pins/peak_counts");
  t.offset_counts = get("/offset_counts").at(0);
  t.rig_file_offset_counts = get("/rig_file_offset_counts").at(0);
  t.total_volume_mm3 = get("/total_volume_mm3").at(0);
  return t;
}

}  // namespace bead::sim
